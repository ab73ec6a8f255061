"""Type stubs of the rsts package (the extension module rsts._rsts)."""

from typing import Any, Callable, Dict, List, Optional, Sequence, Union, overload

import numpy as np
import numpy.typing as npt

__version__: str
#: The built-in integration methods: "rk4", "dopri5", "dop853", "taylor-f64", "taylor-dd", "taylor-mp".
METHODS: List[str]

ArrayLike = Union[npt.ArrayLike, Sequence[float]]
#: f(x0, times, a, b, rtol, atol) -> array of shape (len(times), 9)
Integrator = Callable[[np.ndarray, np.ndarray, float, float, float, float], np.ndarray]

class Case:
    """A motion on N: fields a > b > 0, the point (m, h) off Σ, the torus, the phases at t = 0.

    Bad values raise ValueError with the CLI's message, naming the arguments.
    """

    a: float
    b: float
    m: float
    h: float
    torus: int
    phase1: float
    phase2: float
    #: The camera of (m, h): "I+", "I-", "II+", ..., "VI".
    camera: str

    def __init__(
        self,
        a: float,
        b: float,
        m: float,
        h: float,
        torus: int = 0,
        phase1: float = 0.0,
        phase2: float = 0.0,
    ) -> None: ...
    @staticmethod
    def default() -> "Case":
        """The README's case: camera I+, a = 1, b = 0.5, m = 0.3, h = -0.375."""
    @overload
    def reference(self, times: ArrayLike, digits: None = None) -> "np.ndarray":
        """The exact states at `times`: float64 array (len(times), 9), as `rsts reference`."""
    @overload
    def reference(self, times: ArrayLike, digits: int) -> List[List[str]]:
        """The exact states at `times` as decimal strings of `digits` digits."""

def identify(
    state: ArrayLike, a: float = 1.0, b: float = 0.5, tolerance: float = 1e-9
) -> Dict[str, Any]:
    """Which motion of N a state (omega, alpha, beta) is on: `rsts identify --format json`."""

def compare(
    integrator: Union[str, Integrator],
    case: Optional[Case] = None,
    t_end: float = 100.0,
    samples: int = 1001,
    rtol: float = 1e-10,
    atol: float = 1e-10,
    digits: Optional[int] = None,
) -> Dict[str, Any]:
    """A method name or a callable against the exact motion: `rsts compare --format json`."""

def bench(
    integrators: Union[str, Integrator, Sequence[Union[str, Integrator]]],
    case: Optional[Case] = None,
    tolerances: Sequence[float] = (1e-6, 1e-8, 1e-10),
    t_end: float = 100.0,
    samples: int = 101,
    repeats: int = 3,
    digits: Optional[int] = None,
) -> Dict[str, Any]:
    """Method names and callables, mixed, at each tolerance (rtol = atol): max error, correct
    digits, time (median of `repeats`; a callable's measured around its call), steps and
    evaluations per row, tolerance fits: `rsts bench --format json`."""

def check(
    times: ArrayLike,
    states: ArrayLike,
    a: float = 1.0,
    b: float = 0.5,
    m: Optional[float] = None,
    h: Optional[float] = None,
    torus: Optional[int] = None,
    phase1: Optional[float] = None,
    phase2: Optional[float] = None,
    digits: Optional[int] = None,
    name: str = "arrays",
) -> Dict[str, Any]:
    """A trajectory (times, states) against the exact motion: `rsts check FILE --format json`."""

def convergence(
    methods: Sequence[str],
    steps: Sequence[float],
    case: Optional[Case] = None,
    t_end: float = 10.0,
    samples: int = 11,
    order: Optional[int] = None,
    digits: int = 40,
) -> Dict[str, Any]:
    """Built-in methods at fixed steps, their observed orders: `rsts convergence --format json`."""


def events(
    names: Sequence[str],
    m: float = 0.3,
    h: float = -0.375,
    a: float = 1.0,
    b: float = 0.5,
    torus: int = 0,
    phase1: float = 0.0,
    phase2: float = 0.0,
    t_start: float = 0.0,
    t_end: float = 10.0,
    digits: Optional[int] = None,
) -> Dict[str, Any]:
    """Exact event times in (t_start, t_end] (``rsts events --format json``): zeros of
    omega1..beta3, gamma1..3 and turning points s1, s2, names optionally with ':up'/':down'."""
    ...
