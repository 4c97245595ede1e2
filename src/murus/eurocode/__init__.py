"""Eurocode checks and coefficients. Each function cites its clause.

- :mod:`murus.eurocode.ec8`: EN 1998-1 elastic, vertical and design response spectra.
- :mod:`murus.eurocode.ec6`: EN 1996-1-1 compressed length of a wall section
  (Mordant et al. (SERIES), §2.2.1).
- :mod:`murus.eurocode.ntc`: NTC 2018 (Italy) §3.2.3.2 elastic acceleration and displacement
  spectra from ag, F0, Tc*, soil and topographic categories.
"""
