"""The reports: HTML and PDF from a stored or in-memory result; a report never recomputes dynamics."""
