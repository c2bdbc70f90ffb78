"""One-line profiles from arrays, in the call shapes of the Robotics Toolbox for Python.

No robot and no problem: positions in, samples out, as ``roboticstoolbox`` users write them
(``jtraj``, ``mtraj``, ``quintic``, ``trapezoidal``, ``mstraj``, ``ctraj``; the call shapes and
result fields of ``roboticstoolbox/tools/trajectory.py``), computed with optraj's own profile
maths. Each result also carries ``trajectory``, the same motion as an optraj
:class:`~optraj.planners.Trajectory` for the checker, the controllers and the exports. Bad
input raises :class:`~optraj.errors.InvalidInputError` (a ``ValueError``) naming the argument
and the bound.

>>> from optraj.planners import arrays
>>> tg = arrays.jtraj([0.0, 1.0], [1.0, -1.0], 50)   # 50 samples over the normalised [0, 1]
>>> tg.q.shape, tg.qd.shape
((50, 2), (50, 2))
>>> float(arrays.trapezoidal(0.0, 1.0, [0.0, 1.0, 2.0], V=0.75).qd[1])   # cruise at V
0.75

The modules: ``scalar`` (quintic, trapezoidal), ``joint`` (jtraj, mtraj), ``multi_segment``
(mstraj), ``cartesian`` (ctraj); ``result`` (what they return), ``inputs`` (the time argument),
``stacking`` (one-joint trajectories into one).
"""

from optraj.planners.arrays.cartesian import ctraj
from optraj.planners.arrays.joint import jtraj, mtraj
from optraj.planners.arrays.multi_segment import MultiSegmentProfile, SegmentInfo, mstraj
from optraj.planners.arrays.result import SampledProfile
from optraj.planners.arrays.scalar import TrapezoidalProfile, quintic, trapezoidal

__all__ = [
    "MultiSegmentProfile",
    "SampledProfile",
    "SegmentInfo",
    "TrapezoidalProfile",
    "ctraj",
    "jtraj",
    "mstraj",
    "mtraj",
    "quintic",
    "trapezoidal",
]
