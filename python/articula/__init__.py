"""articula: the dynamics of articulated avatars (BVH takes, URDF robots) as numpy arrays.

The same library and the same numbers as the `articula` command line: ``load(path,
**take_options)`` reads a take as ``articula COMMAND TAKE --flag ...`` does, and each command
(``inverse_dynamics``, ``anatomy``, ``simulate``, ``export``) returns a :class:`Result` holding
the table the command's CSV holds. SI units throughout. See docs/python.md.
"""

from ._native import ArticulaError, Model, Result, Take, __version__, load

__all__ = ["ArticulaError", "Model", "Result", "Take", "__version__", "load"]
