"""Small shared inputs for the tests of murus.studies: short synthetic records (no data
files), a plan of a few dozen histories."""

import numpy as np

from murus.motion import GroundMotion
from murus.rocking import restrained_wall_block
from murus.studies.spectrum import spectrum_case
from murus.studies.study import make_study


def synthetic_records(n: int = 4, seconds: float = 6.0, seed: int = 11):
    """Band-limited noise records of a few seconds, PGA 2.5-5 m/s² (enough to rock block1)."""
    rng = np.random.default_rng(seed)
    dt = 0.01
    out = []
    m = int(seconds / dt)
    t = np.arange(m) * dt
    env = np.minimum(1.0, t / 1.0) * np.exp(-np.maximum(t - 3.0, 0.0))
    for i in range(n):
        a = np.convolve(rng.standard_normal(m + 40), np.ones(12) / 12, mode="same")[:m] * env
        a *= (2.5 + 2.5 * i / max(n - 1, 1)) / np.abs(a).max()
        out.append(GroundMotion(dt, a, name=f"syn{i}", meta={"event": f"synthetic {i}"}))
    return out


def small_study(records, n_k: int = 6, chunk_size: int = 8):
    """block1 of EURODYN (2020), K/K_d in [0, 1] (eq. 11 walls), x 2 scale factors x the records."""
    case = spectrum_case(restrained_wall_block("block1"))
    return make_study(case, {"K_over_Kd": np.linspace(0.0, 1.0, n_k),
                             "motion.scale": [0.6, 1.0]}, records, name="small",
                      chunk_size=chunk_size)


def study_toml(name: str = "t", chunk_size: int = 8,
               k_over_kd: str = "[0.0, 0.5, 1.0]") -> str:
    """A study case file over the records of the folder ``recs`` (see :func:`write_study`):
    block1 of EURODYN (2020) (0.3 x 3.0 m, 21 kN/m³), one-sided with the transverse walls of
    eq. 11, swept over ``K_over_Kd`` (a TOML value: a list or ``{ linspace = [...] }``)."""
    return (f'[study]\nname = "{name}"\nchunk_size = {chunk_size}\n\n'
            "[case.body]\nwidth = 0.3\nheight = 3.0\ndensity = 2140.7\n\n"
            '[case.restraint]\nmotion_sides = "one"\n\n'
            '[case.restraint.transverse_walls]\nstiffness = "eq11"\n\n'
            f"[sweep]\nK_over_Kd = {k_over_kd}\n\n"
            '[records]\nfolder = "recs"\nunits = "m/s2"\n')


def write_study(folder, records, text: str, n_records: int = 2):
    """Write the first ``n_records`` records as CSV into ``folder/recs`` and ``text`` as
    ``folder/s.toml``; return the path of the case file."""
    from pathlib import Path

    from murus.motion import write

    folder = Path(folder)
    (folder / "recs").mkdir(exist_ok=True)
    for m in records[:n_records]:
        write(m, folder / "recs" / f"{m.name}.csv")
    (folder / "s.toml").write_text(text)
    return folder / "s.toml"


#: The small study made slow: 12 chunks of 2 histories (tests/studies/test_studies_interrupt.py
#: and benchmarks/bench_interrupt.py send their signals while it runs).
SLOW_STUDY = study_toml("slow", 2, "{ linspace = [0.0, 1.0, 12] }")

#: ``python -c SLOW_CHILD <sleep [s]> <murus arguments>``: the ``murus`` command with a hook that
#: sleeps at the start of every chunk (:class:`murus.studies.faults.Sleep`).
SLOW_CHILD = """\
import functools, sys
import murus.studies.sweep as sweep
from murus.studies.faults import Sleep
sweep.run_plan = functools.partial(sweep.run_plan, hook=Sleep(float(sys.argv[1])))
sys.argv = ["murus", *sys.argv[2:]]
from murus.cli import app
app()
"""


def children(pid: int) -> list[int]:
    """The processes whose parent is ``pid`` (from /proc)."""
    from pathlib import Path

    out = []
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            try:
                stat = (d / "stat").read_text()
            except OSError:
                continue
            if int(stat.rsplit(")", 1)[1].split()[1]) == pid:
                out.append(int(d.name))
    return out


def alive(pid: int) -> bool:
    """Whether ``pid`` runs (a zombie does not)."""
    from pathlib import Path

    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat.rsplit(")", 1)[1].split()[0] != "Z"
