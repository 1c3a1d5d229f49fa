"""The scaling issue's chain in Exudyn, for `docs/performance.md` ("Exudyn side by side").

N rigid links (1 kg, 0.2 m, a 10 mm rod: the values of scenes/scaling.toml's [chain]) on
revolute joints about world y, hinged to ground at the origin, horizontal along +x at
rest, falling under g = 9.81 m/s^2 along -z for 0.3 s. Exudyn's generalized-alpha with
its sparse LU (EigenSparse), fixed step. Prints one JSON line per run: the last link's
centre of mass at 0.3 s and the wall time of the whole process part (build + solve).

    venv/bin/python chain.py N STEPS [STEPS ...]
"""

import json
import sys
import time

import exudyn as exu
from exudyn.utilities import RigidBodyInertia
import numpy as np

M, L, R, G, T = 1.0, 0.2, 0.01, 9.81, 0.3


def run(n, steps):
    t0 = time.perf_counter()
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.CreateGround()
    across = M * L * L / 12.0 + M * R * R / 4.0
    inertia = RigidBodyInertia(mass=M, inertiaTensor=np.diag([0.5 * M * R * R, across, across]))
    prev = ground
    last = None
    for k in range(n):
        b = mbs.CreateRigidBody(
            inertia=inertia,
            referencePosition=[(k + 0.5) * L, 0.0, 0.0],
            gravity=[0.0, 0.0, -G],
        )
        mbs.CreateRevoluteJoint(itemNumbers=[prev, b], position=[k * L, 0.0, 0.0], axis=[0.0, 1.0, 0.0])
        prev = b
        last = b
    mbs.Assemble()
    s = exu.SimulationSettings()
    s.timeIntegration.endTime = T
    s.timeIntegration.numberOfSteps = steps
    s.timeIntegration.verboseMode = 0
    s.solution.file.write = False
    s.solution.sensors.writePeriod = T
    s.linearSolver.solverType = exu.LinearSolverType.EigenSparse
    s.timeIntegration.generalizedAlpha.spectralRadius = 0.9
    s.show.statistics = False
    s.show.computationTime = False
    ok = mbs.SolveDynamic(s, solverType=exu.DynamicSolverType.GeneralizedAlpha)
    tip = mbs.GetObjectOutputBody(last, exu.OutputVariableType.Position, localPosition=[0, 0, 0])
    wall = time.perf_counter() - t0
    return {"n": n, "steps": steps, "ok": bool(ok), "tip_m": [float(x) for x in tip], "wall_s": wall}


if __name__ == "__main__":
    n = int(sys.argv[1])
    for st in sys.argv[2:]:
        print(json.dumps(run(n, int(st))), flush=True)
