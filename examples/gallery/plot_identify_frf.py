"""
White-noise identification of a shaking-table test (Mordant et al. (SERIES), §2.1)
==================================================================================

A virtual white-noise test of a wall in the test-file format of murus (the truth is known), its
H1 frequency response and coherence, and the natural frequency and damping identified by the
half-power bandwidth and a modal fit.
"""

import matplotlib.pyplot as plt

from murus.identify import frf, identify, synthesize_tests

tests, truth = synthesize_tests(seed=0, levels=(0.04,), wn_duration=60.0)
test = tests[0]
result = identify(test)
for mode in result.modes:
    print(f"f = {mode.frequency:.3f} Hz, zeta = {mode.damping:.3%} "
          f"(half power {mode.damping_half_power:.3%}), reliable: {not mode.warnings}")
print("truth:", truth[0] if isinstance(truth, (list, tuple)) else truth)

H = frf(test)
fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 5), sharex=True)
ax1.semilogy(H.f, abs(H.H))
ax1.set_ylabel("|H1|")
ax2.plot(H.f, H.coherence)
ax2.set_ylabel("coherence")
ax2.set_xlabel("f [Hz]")
ax2.set_xlim(0, 40)
plt.tight_layout()
