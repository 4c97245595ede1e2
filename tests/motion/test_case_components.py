"""The [motion] table's ``channel`` and ``vertical`` keys: a multi-channel record read for a
case, with the vertical channel carried as ``acc_v`` to the engines."""

import shutil
from pathlib import Path

import numpy as np
import pytest
from pydantic import ValidationError

from murus.config import CaseError
from murus.dem.case import MotionCfg as DemMotion
from murus.motion.case import build_motion
from murus.motion.io import read_all
from murus.rocking.case import MotionCfg as RockingMotion
from murus.rocking.excitation import as_excitation

CLC = Path(__file__).resolve().parents[1] / "data" / "records" / "CICLC_trim.v1"


def test_record_channel_and_vertical(tmp_path):
    shutil.copy(CLC, tmp_path / "clc.v1")
    case = tmp_path / "case.toml"
    text = "[motion]\nfile = 'clc.v1'\nchannel = '360'\nvertical = true\n"
    case.write_text(text)
    chans = read_all(CLC)
    gm = build_motion(RockingMotion(file="clc.v1", channel="360", vertical=True, scale=0.5),
                      case, text)
    assert np.array_equal(gm.acc, 0.5 * chans[1].acc)
    assert np.array_equal(gm.acc_v, 0.5 * chans[2].acc)
    ex = as_excitation(gm)  # what the rocking engine takes: the vertical is kept
    assert ex.acc_v is not None and np.array_equal(ex.acc_v, gm.acc_v)
    gm2 = build_motion(DemMotion(file="clc.v1", channel=1), case, text)
    assert np.array_equal(gm2.acc, chans[0].acc) and gm2.acc_v is None
    with pytest.raises(CaseError, match=r"line 2: \[motion.file\] motion file clc.v1: no "
                                        "channel matches channel 'west'"):
        build_motion(RockingMotion(file="clc.v1", channel="west"), case, text)


def test_vertical_from_a_separate_file(tmp_path):
    from test_io_networks import _counts, _knet_text

    (tmp_path / "s.NS").write_text(_knet_text(_counts(seed=1), direction="N-S"))
    (tmp_path / "s.UD").write_text(_knet_text(_counts(seed=2), direction="U-D"))
    case = tmp_path / "case.toml"
    text = "[motion]\nfile = 's.NS'\nvertical = 's.UD'\n"
    case.write_text(text)
    gm = build_motion(RockingMotion(file="s.NS", vertical="s.UD"), case, text)
    assert np.array_equal(gm.acc_v, read_all(tmp_path / "s.UD")[0].acc)


def test_channel_only_with_a_record():
    with pytest.raises(ValidationError, match="channel and vertical go with a record file"):
        RockingMotion(type="sine-pulse", amplitude=1.0, frequency=2.0, vertical=True)
