"""Make plain-text notation of the docstrings safe for reStructuredText (Sphinx extension).

The docstrings of murus write absolute values and norms as ``|a|`` and file globs as ``*.csv``,
which reads well in ``help()`` and in the CLI's ``--help`` but which reStructuredText takes for
substitution references and emphasis. This hook escapes those characters before numpydoc and
autodoc parse the docstring, outside inline literals and roles (backticks), literal blocks
(``::``), directives' bodies (``.. math::``) and doctests, so the source stays as it is.
"""

from __future__ import annotations

import re

_SPLIT = re.compile(r"(``.+?``|:[\w:.-]+:`[^`]*`|`[^`]*`_?)")
_GLOB = re.compile(r"(?<![\\*\w])\*{1,2}(?=[.\w{\[])(?![^\s*]*\*+(?:\s|$|[.,;:)]))")


def _escape_text(text: str) -> str:
    parts = _SPLIT.split(text)
    for i in range(0, len(parts), 2):  # even indices: outside literals and roles
        part = parts[i]
        part = re.sub(r"(?<!\\)\|", r"\\|", part)
        part = _GLOB.sub(lambda m: "\\*" * len(m.group()), part)
        parts[i] = part
    return "".join(parts)


def _indent(line: str) -> int:
    return len(line) - len(line.lstrip())


def escape_lines(lines: list[str]) -> None:
    """Escape ``|`` and unmatched ``*`` in ``lines`` in place (see the module docstring)."""
    block_indent = None  # indent of the line that opened a literal block or a directive
    for i, line in enumerate(lines):
        stripped = line.strip()
        if block_indent is not None:
            if not stripped or _indent(line) > block_indent:
                continue
            block_indent = None
        if stripped.startswith(">>>") or stripped.startswith("..."):
            continue
        if stripped.startswith(".. ") or stripped.endswith("::"):
            block_indent = _indent(line)
            if stripped.startswith(".. "):
                continue
        if stripped.startswith(("|", "+")) and stripped.endswith(("|", "+")):
            continue  # a table row
        lines[i] = _escape_text(line)


def _process(app, what, name, obj, options, lines):
    escape_lines(lines)


def setup(app):
    # before numpydoc (priority 500), which parses the sections
    app.connect("autodoc-process-docstring", _process, priority=100)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
