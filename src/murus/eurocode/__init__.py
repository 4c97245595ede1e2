"""Eurocode checks and coefficients. Each function cites its clause.

- :mod:`murus.eurocode.ec8`: EN 1998-1 elastic, vertical and design response spectra.
"""
