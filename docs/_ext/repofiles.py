"""Bring the repository's Markdown files into the site at build time (Sphinx extension).

README.md, VALIDATION.md, BENCHMARKS.md, CONTRIBUTING.md and CHANGELOG.md live at the root of the
repository and are written for GitHub: their links point to files of the repository. At each
build this hook copies them into ``docs/_generated/`` with those links rewritten (a file that is a
page of the site becomes a link to the page, an image under ``docs/`` keeps working, another file
of the repository becomes plain text), and the pages include the copies. The text itself is
never copied by hand: ``make validate`` and ``make bench`` rewrite the sources, the next build
shows them.
"""

from __future__ import annotations

import re
from pathlib import Path

FILES = ("README.md", "VALIDATION.md", "BENCHMARKS.md", "CONTRIBUTING.md", "CHANGELOG.md")

# repository path -> page of the site (absolute docname)
PAGES = {
    "README.md": "/index",
    "VALIDATION.md": "/validation",
    "BENCHMARKS.md": "/benchmarks",
    "CONTRIBUTING.md": "/contributing",
    "CHANGELOG.md": "/changelog",
    "docs/architecture.md": "/architecture",
    "docs/references.md": "/references",
    "docs/retaining_backfills.md": "/guide/retaining_backfills",
}

_LINK = re.compile(r"(!?)\[((?:[^\[\]]|\[[^\]]*\])*)\]\(([^)\s]+)\)")


def _rewrite(text: str) -> str:
    def repl(m: re.Match) -> str:
        bang, label, target = m.groups()
        if re.match(r"^[a-z][a-z0-9+.-]*:", target) or target.startswith("#"):
            return m.group(0)  # a URL or an anchor of the same page
        path, _, anchor = target.partition("#")
        path = path.rstrip("/")
        if bang:  # an image: the files under docs/ are next to the pages
            if path.startswith("docs/"):
                return f"{bang}[{label}](../{path[5:]})"
            return m.group(0)
        if path in PAGES:
            plain = label.replace("`", "")
            return f"{{doc}}`{plain} <{PAGES[path]}>`"
        if path.startswith("docs/figures/"):
            return f"[{label}](../{path[5:]})"
        return label  # another file of the repository: its name, as text
    return _LINK.sub(repl, text)


def generate(root: Path, outdir: Path) -> None:
    outdir.mkdir(parents=True, exist_ok=True)
    for name in FILES:
        src = root / name
        if not src.is_file():
            continue
        text = _rewrite(src.read_text(encoding="utf-8"))
        dst = outdir / name
        if not dst.exists() or dst.read_text(encoding="utf-8") != text:
            dst.write_text(text, encoding="utf-8")


def _on_builder_inited(app):
    srcdir = Path(app.srcdir)
    generate(srcdir.parent, srcdir / "_generated")


def setup(app):
    app.connect("builder-inited", _on_builder_inited)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
