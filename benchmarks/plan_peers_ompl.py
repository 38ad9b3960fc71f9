"""OMPL's RRT-Connect on one problem of benchmarks/plan/, for benchmarks/plan_peers.py: the joint
limits as bounds, kinema's Robot.collides (the problem's scene, margin 0) as state validity, OMPL's
discrete motion validator at a given step, configuration start and goal, 1 s, then SimpleSetup's
path simplifier (timed with the search, as kinema's shortening is)."""

import numpy as np
from ompl import base as ob
from ompl import geometric as og
from ompl import util as ou

ou.setLogLevel(ou.LOG_WARN)


def plan(robot, scene, start, goal, seed, resolution):
    """(path as configurations, planning time [s]) or None when no exact path was found in 1 s.

    `resolution` [rad] is the L2 step between motion checks; OMPL takes it as a fraction of the space's
    extent. The random seed is OMPL's process-wide one: it is set once, on the first call."""
    if not hasattr(plan, "seeded"):
        ou.RNG.setSeed(seed + 1)
        plan.seeded = True
    n = robot.n
    space = ob.RealVectorStateSpace(n)
    bounds = ob.RealVectorBounds(n)
    for i, (lo, hi) in enumerate(robot.qlim.T):
        bounds.setLow(i, float(lo))
        bounds.setHigh(i, float(hi))
    space.setBounds(bounds)
    setup = og.SimpleSetup(space)
    q = np.empty(n)

    def valid(state):
        for i in range(n):
            q[i] = state[i]
        return not robot.collides(q, scene)

    setup.setStateValidityChecker(valid)
    info = setup.getSpaceInformation()
    info.setStateValidityCheckingResolution(resolution / space.getMaximumExtent())
    a, b = space.allocState(), space.allocState()
    for i in range(n):
        a[i], b[i] = float(start[i]), float(goal[i])
    setup.setStartAndGoalStates(a, b)
    setup.setPlanner(og.RRTConnect(info))
    setup.solve(1.0)
    if not setup.haveExactSolutionPath():
        return None
    # kinema's planning time includes its shortening, so OMPL's includes its simplifier's.
    setup.simplifySolution()
    path = setup.getSolutionPath()
    states = [np.array([path.getState(k)[i] for i in range(n)]) for k in range(path.getStateCount())]
    return states, setup.getLastPlanComputationTime() + setup.getLastSimplificationTime()
