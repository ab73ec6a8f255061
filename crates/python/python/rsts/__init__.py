"""rsts: exact reference motions and integrator checks for the Kowalevski top in two constant
fields (the Reyman–Semenov-Tian-Shansky problem), from Python.

The Python face of the ``rsts`` command-line tool, built from the same Rust crates:

- ``rsts.Case(a, b, m, h, torus=0, phase1=0.0, phase2=0.0)``: a motion on the invariant
  manifold N, checked as the CLI checks it; ``Case.default()`` is the README's case;
- ``case.reference(times, digits=None)``: the exact states, equal bit for bit to
  ``rsts reference``;
- ``rsts.identify(state, a, b)``: which motion of N a state is on (``rsts identify``);
- ``rsts.compare(integrator, case=None, ...)``: a built-in method or your Python integrator
  against the exact motion (``rsts compare``);
- ``rsts.bench(integrators, case=None, tolerances=(1e-6, 1e-8, 1e-10), ...)``: method names and
  Python integrators, mixed, their error against their cost at each tolerance (``rsts bench``);
- ``rsts.check(times, states, a, b, ...)``: a trajectory you computed against the exact motion
  (``rsts check``);
- ``rsts.convergence(methods, steps, case=None, ...)``: built-in methods at fixed steps and their
  observed orders (``rsts convergence``);
- ``rsts.events(names, m, h, ...)``: exact event times along a motion (``rsts events``).

Reports are the CLI's ``--format json`` documents, as dicts. See docs/python.md.
"""

from ._rsts import METHODS, Case, __version__, bench, check, compare, convergence, events, identify

__all__ = ["Case", "METHODS", "bench", "check", "compare", "convergence", "events", "identify", "__version__"]
