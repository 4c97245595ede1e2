"""The ``lab`` command group (murus.identify.cli) through typer's CliRunner: outputs, one-line
errors with exit code 2, nothing written on error."""

import json

import pytest
from typer.testing import CliRunner

from murus.identify.cli import app
from murus.outputs import MANIFEST

runner = CliRunner()


@pytest.fixture(scope="module")
def seq(tmp_path_factory):
    out = tmp_path_factory.mktemp("cli") / "seq"
    r = runner.invoke(app, ["synthesize", str(out), "--seed", "5", "--levels", "0.04,0.32",
                            "--wn-duration", "40"])
    assert r.exit_code == 0, r.output
    return out


def test_synthesize_writes_the_sequence(seq):
    names = sorted(p.name for p in seq.iterdir() if p.name != MANIFEST)
    assert names == ["01_WN01.csv", "02_S01.csv", "03_WN02.csv", "04_S02.csv", "05_WN03.csv",
                     "sequence.toml", "truth.json"]


def test_frf(seq, tmp_path):
    r = runner.invoke(app, ["frf", str(seq / "01_WN01.csv"), "--out", str(tmp_path / "o")])
    assert r.exit_code == 0, r.output
    assert "| 1 |" in r.output
    files = sorted(p.name for p in (tmp_path / "o").iterdir() if p.name != MANIFEST)
    assert files == ["frf.png", "frf.svg", "modes.json", "modes.md"]
    d = json.loads((tmp_path / "o" / "modes.json").read_text())
    truth = json.loads((seq / "truth.json").read_text())["tests"][0]
    assert d["modes"][0]["frequency"] == pytest.approx(truth["frequency_hz"], rel=0.02)
    # without --out: print only
    r = runner.invoke(app, ["frf", str(seq / "01_WN01.csv")])
    assert r.exit_code == 0 and "mode(s)" in r.output


def test_sequence_report(seq, tmp_path):
    out = tmp_path / "rep"
    r = runner.invoke(app, ["sequence", str(seq), "--out", str(out)])
    assert r.exit_code == 0, r.output
    files = {p.name for p in out.iterdir()}
    for f in ("frequency.png", "frequency.svg", "damping.png", "damping.svg",
              "compressive_length.png", "compressive_length.csv", "report.md",
              "summary.json", "rotations_S01.png", "rotations_S02.svg", "lifted_S02.png",
              "lifted_S01.svg"):
        assert f in files
    rep = (out / "report.md").read_text()
    assert "Table 2" in rep and "| S01 | cantilever |" in rep and "| S02 | rocking |" in rep
    s = json.loads((out / "summary.json").read_text())
    assert len(s["evolution"]) == 3 and s["classification"][0]["class"] == "cantilever"
    # the cantilever section: E_eff = E (f1 / f1,model)^2 for each white-noise test
    c = s["cantilever"]
    assert "## Cantilever model" in rep
    for row, ev in zip(c["tests"], s["evolution"], strict=True):
        assert row["E_eff_pa"] == pytest.approx(
            c["modulus_pa"] * (ev["f1_hz"] / c["f1_model_hz"]) ** 2, rel=1e-9)
    # the library function behind the command gives the same summary and report
    from murus.identify import process_sequence

    lib = process_sequence(seq)
    assert json.loads(json.dumps(lib.summary(), default=str)) == json.loads(
        json.dumps(s, default=str))
    figs = ["frequency.png", "damping.png", "compressive_length.png"]
    assert lib.markdown(figs) == rep


def _one_line_error(r):
    assert r.exit_code == 2
    err = r.stderr if hasattr(r, "stderr") else r.output
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: ")
    return lines[0]


def test_errors_exit_2_and_write_nothing(seq, tmp_path):
    out = tmp_path / "never"
    msg = _one_line_error(runner.invoke(app, ["frf", str(tmp_path / "nope.csv"), "--out",
                                              str(out)]))
    assert "no such file" in msg and not out.exists()
    bad = tmp_path / "bad"
    bad.mkdir()
    txt = (seq / "02_S01.csv").read_text().splitlines()
    txt[20] = txt[20].replace(",", ",nan,", 1).replace(",nan,", ",nan", 1)
    (bad / "01_S01.csv").write_text("\n".join(txt) + "\n")
    msg = _one_line_error(runner.invoke(app, ["sequence", str(bad), "--out", str(out)]))
    assert "01_S01.csv:21" in msg and not out.exists()
    # a sequence without white-noise tests cannot give the frequency evolution
    (bad / "01_S01.csv").write_text((seq / "02_S01.csv").read_text())
    msg = _one_line_error(runner.invoke(app, ["sequence", str(bad), "--out", str(out)]))
    assert "no white-noise test" in msg and not out.exists()
    msg = _one_line_error(runner.invoke(app, ["synthesize", str(seq)]))
    assert "not an empty folder" in msg
    msg = _one_line_error(runner.invoke(app, ["synthesize", str(out), "--levels", "a,b"]))
    assert "--levels" in msg and not out.exists()
    msg = _one_line_error(runner.invoke(app, ["sequence", str(seq), "--out", str(out),
                                              "--cantilever-below", "0.9"]))
    assert "--rocking-above" in msg and not out.exists()


def test_help_keeps_bracketed_units():
    r = runner.invoke(app, ["sequence", "--help"])
    assert r.exit_code == 0 and "[m]" in r.output and "[rad]" in r.output


def test_modes_zero_refused(seq, tmp_path):
    """``--modes 0`` would give an empty table: refused before reading (issue 15, item 8)."""
    for cmd in (["frf", str(seq / "01_WN01.csv")], ["sequence", str(seq)]):
        r = runner.invoke(app, [*cmd, "--modes", "0", "--out", str(tmp_path / "o")])
        assert r.exit_code == 2 and "--modes" in r.output
        assert not (tmp_path / "o").exists()
