"""Mohr-Coulomb continuum zones beside the distinct elements (issue 17)."""
