"""draco-mbd from Python (docs/python.md).

Linear systems (tf, ss, TransferFunction, StateSpace; series, parallel, feedback; c2d),
their analysis as NumPy arrays (poles, zeros, bode, freqresp, step, margins), block
diagrams (load_diagram, Diagram.linearize), code generation (generate_code),
scenarios (run_scenario: logs as NumPy arrays, metrics as a dict) and robot models
(load_robot: mass matrix, bias forces, Jacobians as in Pinocchio). Mistakes raise
dmbd.InputError (a ValueError) or one of its kinds, with the library's message
(file:line:column: ... where a file is involved).

    >>> import numpy as np, dmbd
    >>> G = dmbd.tf("1/(s^2 + 2*s + 5)")
    >>> dmbd.poles(G)
    array([-1.-2.j, -1.+2.j])
"""
from . import _dmbd
from ._dmbd import *  # noqa: F401,F403  (every public name of the extension)
from ._dmbd import __version__  # noqa: F401

# The classes are dmbd.TransferFunction, ... (not dmbd._dmbd.TransferFunction) in
# reprs and help().
for _name in dir(_dmbd):
    _obj = getattr(_dmbd, _name)
    if isinstance(_obj, type) and _obj.__module__ == _dmbd.__name__:
        _obj.__module__ = __name__
del _name, _obj
