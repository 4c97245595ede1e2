"""Replace one section of VALIDATION.md by a freshly generated one, without running the others
(``make validate`` regenerates them all): the section is the text from the line that starts
with ``heading`` (a level-2 heading, ``## ...``) to the next level-2 heading or the end.

Usage::

    python validation/retaining_continuum.py --cached --out /tmp/rc.md
    python validation/splice.py VALIDATION.md /tmp/rc.md "## Dry-stone retaining walls on the c"

The new text must start with a line that starts with ``heading`` too. Exit code 2, and the file
left as it was, when either heading is missing or found twice.
"""

from __future__ import annotations

import sys
from pathlib import Path


def splice(doc: str, new: str, heading: str) -> str:
    """``doc`` with its section ``heading`` (module doc) replaced by ``new``."""
    lines = doc.splitlines(keepends=True)
    starts = [i for i, ln in enumerate(lines) if ln.startswith(heading)]
    if len(starts) != 1:
        raise ValueError(f"{len(starts)} lines of the document start with {heading!r} (need 1)")
    if not new.lstrip("\n").startswith(heading):
        raise ValueError(f"the new text does not start with {heading!r}")
    a = starts[0]
    b = next((i for i in range(a + 1, len(lines)) if lines[i].startswith("## ")), len(lines))
    body = new.strip("\n") + "\n"
    if b < len(lines):
        body += "\n"
    return "".join(lines[:a]) + body + "".join(lines[b:])


def main(argv=None) -> None:
    args = sys.argv[1:] if argv is None else argv
    if len(args) != 3:
        print("usage: splice.py DOCUMENT NEW_SECTION HEADING", file=sys.stderr)
        raise SystemExit(2)
    doc, new, heading = Path(args[0]), Path(args[1]), args[2]
    try:
        out = splice(doc.read_text(), new.read_text(), heading)
    except (OSError, ValueError) as e:
        print(f"error: {e}", file=sys.stderr)
        raise SystemExit(2) from None
    from murus.outputs import write_text

    write_text(doc, out)


if __name__ == "__main__":
    main()
