"""Published evaluation protocols (ARiADNE's test driver, Explore-Bench's metrics), run as their
papers' code runs them."""
