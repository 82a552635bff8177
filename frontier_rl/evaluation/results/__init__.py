"""A results folder as typed values: the store of rows, traces and checksums, their files, an
episode's row and trace, and the experiment's summary."""
