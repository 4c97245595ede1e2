"""The preset names of the previous release still work for one release, with a DeprecationWarning
(issue 16 item 5: presets are named after the physics, not after internal paper handles)."""

import numpy as np
import pytest

from murus.rocking import restrained_wall_block, series_clay_wall
from murus.studies import restraint_configs


def test_seed002_block_is_a_deprecated_alias():
    from murus.rocking import seed002_block

    with pytest.warns(DeprecationWarning, match="restrained_wall_block"):
        old = seed002_block("block3")
    new = restrained_wall_block("block3")
    assert (old.width, old.height, old.density) == (new.width, new.height, new.density)


def test_seed000_wall_is_a_deprecated_alias():
    from murus.rocking import seed000_wall

    with pytest.warns(DeprecationWarning, match="series_clay_wall"):
        old = seed000_wall("long")
    new = series_clay_wall("long")
    assert (old.width, old.height, old.top_mass) == (new.width, new.height, new.top_mass)


def test_seed002_configs_and_constants_are_deprecated_aliases():
    from murus.studies import seed002_configs
    from murus.studies.spectrum import TIE_STIFFNESS_RATIOS

    b = restrained_wall_block("block1")
    with pytest.warns(DeprecationWarning, match="restraint_configs"):
        old = seed002_configs(b, c_over_cd=0.05)
    assert list(old) == list(restraint_configs(b, c_over_cd=0.05))
    with pytest.warns(DeprecationWarning, match="RESTRAINED_WALL_UNIT_WEIGHT"):
        from murus.rocking.body import SEED002_UNIT_WEIGHT
    assert SEED002_UNIT_WEIGHT == 21000.0
    with pytest.warns(DeprecationWarning, match="TIE_STIFFNESS_RATIOS"):
        from murus.studies.spectrum import SEED002_RATIOS
    np.testing.assert_array_equal(SEED002_RATIOS, TIE_STIFFNESS_RATIOS)


def test_deprecated_names_stay_out_of_all():
    import murus.rocking
    import murus.studies

    assert "seed002_block" not in murus.rocking.__all__
    assert "seed002_configs" not in murus.studies.__all__
