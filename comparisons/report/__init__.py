"""Reports: the table and document types, their Markdown, HTML and CSV renderers, and one
builder per command (``compare`` and its other-law variant, the tuned-scene study, the
pre-impact rows)."""
