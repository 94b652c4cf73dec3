"""Docs written by code: each module regenerates one part of docs/ from a command's output
(``python -m comparisons.docs NAME``), and the tests fail when the docs' numbers drift from
what the code gives."""
