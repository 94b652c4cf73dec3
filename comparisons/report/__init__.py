"""Reports, through one pipeline: the typed document (``document``, ``tables``, the one number
format ``number_format``), one Markdown and CSV renderer (``render``), one HTML renderer
(``html``), one writer (``write``), and one builder per command (``compare`` with
``compare_tables`` and ``compare_document``, ``law``, ``reconstruct``, ``validate``,
``hard_cases``, ``speed_error``, ``pulses``, ``tuned``, ``assumptions``; the pre-impact rows
``pre_impact``)."""
