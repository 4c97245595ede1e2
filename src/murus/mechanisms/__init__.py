"""Kinematic checks of local out-of-plane mechanisms of masonry façades (NTC 2018, Circolare 2019
n. 7 §C8.7.1.2.1): simple overturning of one or several storeys (every hinge level), vertical
flexure of a wall restrained at top and bottom, overturning of a corner wedge; linear
(activation acceleration a0*) and nonlinear (capacity curve, displacement demand) checks at the
limit states SLD, SLV and SLC, with the floor spectra of §C7.2.3 for mechanisms above the ground.

Sign convention (:mod:`murus.mechanisms.kinematics`): x outward (the direction of overturning),
y upward, origin at the outer face of the wall at the foundation. SI units.

The names below are imported on first use (PEP 562).

>>> from murus.mechanisms import SimpleOverturning, Storey, alpha
>>> wall = SimpleOverturning([Storey(height=4.0, thickness=0.5, density=1800.0)], [])
>>> round(alpha(wall), 6)   # b / h of a monolithic wall
0.125
"""

from murus._lazy import lazy_exports

_EXPORTS = {
    "MechanismError": "kinematics",
    "Storey": "kinematics",
    "Floor": "kinematics",
    "Mechanism": "kinematics",
    "SimpleOverturning": "kinematics",
    "VerticalFlexure": "kinematics",
    "CornerOverturning": "kinematics",
    "alpha": "kinematics",
    "participation": "kinematics",
    "Building": "demand",
    "EC8Spectrum": "demand",
    "DemandError": "demand",
    "floor_acceleration": "demand",
    "floor_spectrum": "demand",
    "displacement_demand": "demand",
    "Seismic": "checks",
    "Check": "checks",
    "MechanismResult": "checks",
    "analyse": "checks",
    "capacity_curve": "checks",
    "PARAMS": "checks",
    "LIMIT_STATES": "checks",
    "overturning": "facade",
    "vertical_flexure": "facade",
    "flexure_of_storey": "facade",
    "governing": "facade",
    "plot_capacity": "facade",
}

__all__ = sorted(_EXPORTS)

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals(),
                                    ("kinematics", "demand", "checks", "facade", "case"))
