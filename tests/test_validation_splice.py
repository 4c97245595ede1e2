"""validation/splice.py replaces one section of VALIDATION.md and leaves the others as they
were, byte for byte; a heading missing or found twice is refused (exit code 2, file kept)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "validation"))
import splice  # noqa: E402

DOC = "# title\n\nintro\n\n## A one\n\nold a\n\n### sub\n\nx\n\n## B two\n\nb\n"


def test_splice_replaces_one_section_only():
    out = splice.splice(DOC, "## A one (new)\n\nnew a\n", "## A one")
    assert out == "# title\n\nintro\n\n## A one (new)\n\nnew a\n\n## B two\n\nb\n"
    # the last section: up to the end of the document
    assert splice.splice(DOC, "## B two\n\nc\n", "## B two").endswith("## B two\n\nc\n")
    assert splice.splice(DOC, "## B two\n\nc\n", "## B two").startswith(DOC[:DOC.index("## B")])


def test_splice_refuses_and_keeps_the_file(tmp_path, capsys):
    with pytest.raises(ValueError, match="0 lines"):
        splice.splice(DOC, "## C\n", "## C")
    with pytest.raises(ValueError, match="2 lines"):
        splice.splice(DOC + "## A one again\n", "## A one\n", "## A one")
    with pytest.raises(ValueError, match="does not start"):
        splice.splice(DOC, "## B two\n", "## A one")
    doc, new = tmp_path / "V.md", tmp_path / "n.md"
    doc.write_text(DOC)
    new.write_text("## Z\n")
    with pytest.raises(SystemExit) as e:
        splice.main([str(doc), str(new), "## Z"])
    assert e.value.code == 2 and doc.read_text() == DOC
    assert capsys.readouterr().err.startswith("error: 0 lines")
