"""Continuum zones (FLAC/UDEC style) next to the distinct elements (issue 17)."""
