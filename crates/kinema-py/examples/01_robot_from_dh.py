"""A robot defined in code, the way the toolbox's DHRobot reads: Puma 560's
DH table (Corke's mdl_puma560, standard DH), checked against the built-in."""

import numpy as np

import kinema
from kinema import RevoluteDH

pi = np.pi
puma = kinema.Robot.from_dh(
    [
        RevoluteDH(d=0.6718, a=0.0, alpha=pi / 2, qlim=[-2.79, 2.79]),
        RevoluteDH(d=0.0, a=0.4318, alpha=0.0, qlim=[-3.93, 0.79]),
        RevoluteDH(d=0.15005, a=0.0203, alpha=-pi / 2, qlim=[-0.79, 3.93]),
        RevoluteDH(d=0.4318, a=0.0, alpha=pi / 2, qlim=[-1.92, 2.97]),
        RevoluteDH(d=0.0, a=0.0, alpha=-pi / 2, qlim=[-1.74, 1.74]),
        RevoluteDH(d=0.0, a=0.0, alpha=0.0, qlim=[-4.64, 4.64]),
    ],
    name="my-puma",
    poses={"qr": [0, pi / 2, -pi / 2, 0, 0, 0]},
)
print(puma, puma.joint_types)
print(np.round(puma.fkine("qr"), 4))

builtin = kinema.Robot.builtin("puma560")
q = np.random.default_rng(0).uniform(-1, 1, 6)
difference = np.abs(puma.fkine(q) - builtin.fkine(q)).max()
print("largest difference from the built-in puma560:", difference)
assert difference < 1e-12
