#!/usr/bin/env python3
"""Fig. 9 of the paper from Python: rotor speed over excitation frequency,
both models, with the usm package (docs/python.md).

    PYTHONPATH=build/python /usr/bin/python3 examples/fig9.py [OUT.png]
"""
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

import usm

out = sys.argv[1] if len(sys.argv) > 1 else "fig9.png"
fig, ax = plt.subplots(figsize=(8, 5))
for base, colour in (("3dof", "tab:blue"), ("4dof", "tab:red")):
    sweep = usm.Model(base).sweep("f", 30e3, 46e3, points=161, floquet=False)
    speed = -sweep.rotor_speed                      # w_R = -dphi_R/dt [1/s]
    ax.plot(sweep.f / 1e3, speed, color=colour, label=base)
    ok = sweep.valid == 1                           # where the model describes the motor
    best = speed[ok].argmax()
    print("%s: speed maximum %.4g 1/s at %.5g kHz" % (base, speed[ok][best], sweep.f[ok][best] / 1e3))
ax.set_xlabel("excitation frequency f [kHz]")
ax.set_ylabel("rotor speed $\\omega_R$ [1/s]")
ax.set_title("Rotor speed vs excitation frequency (paper Fig. 9)")
ax.grid(True)
ax.legend()
fig.savefig(out, dpi=120)
print("wrote", out)
