"""The report of a paired experiment: its tables, figures, conclusion and the page they make
(Markdown and HTML)."""
