"""Small shared inputs for the tests of murus.dem: the case file of one block on a fixed base."""

#: A 0.4 x 0.2 m stone block (2000 kg/m³, 30 deg friction) resting on a fixed 2.0 x 0.2 m base.
#: Placeholders: ``{duration}`` [s]; ``{dem}``, more lines of ``[dem]``; ``{kn}``, the normal and
#: shear stiffness of the stone joints [Pa/m]; ``{extra}``, more lines of the block's table.
#: Monitors are appended by each test module.
BLOCK_ON_BASE = """\
[dem]
duration = {duration}
{dem}
[materials.stone]
density = 2000.0
kn = {kn}
ks = {kn}
friction_deg = 30.0

[[blocks]]
kind = "rectangle"
width = 2.0
height = 0.2
center = [0.0, -0.1]
kinematic = "fixed"

[[blocks]]
kind = "rectangle"
width = 0.4
height = 0.2
center = [0.0, 0.1]
{extra}
"""
