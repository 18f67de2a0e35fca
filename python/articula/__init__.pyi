"""Type stubs of the articula module (its native part is articula._native)."""

from os import PathLike
from typing import Any, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str

_Path = Union[str, PathLike[str]]
_Repeated = Union[str, float, Sequence[Union[str, float]], Mapping[str, float]]
_Array = npt.ArrayLike

class ArticulaError(Exception):
    """An error of articula; its message names the file, line or option to change."""

def load(
    path: _Path,
    *,
    unit: Optional[str] = ...,
    stature: Optional[float] = ...,
    up: Optional[str] = ...,
    positions: Optional[str] = ...,
    joints: Optional[str] = ...,
    mass: Optional[float] = ...,
    sex: Optional[str] = ...,
    segments: Optional[str] = ...,
    link_mass: Optional[_Repeated] = ...,
    smooth: Optional[str] = ...,
    lock: Optional[Union[str, Sequence[str]]] = ...,
    subtree: Optional[str] = ...,
    contact: Optional[str] = ...,
    keep_first_frame: bool = ...,
    joint_translations: Optional[str] = ...,
    damping: Optional[_Repeated] = ...,
    scene: Optional[_Path] = ...,
) -> Take:
    """Load a BVH take; the keywords are the command line's take flags."""

class Result:
    """A command's table: the columns of its CSV after `time`, one row per frame (SI)."""
    @property
    def time(self) -> npt.NDArray[np.float64]: ...
    @property
    def columns(self) -> list[str]: ...
    @property
    def values(self) -> npt.NDArray[np.float64]: ...
    @property
    def notes(self) -> list[str]: ...
    @property
    def summary(self) -> Optional[dict[str, Any]]: ...
    def peaks(self) -> dict[str, float]:
        """Peak |x| of every column, by name."""
    def rms(self) -> dict[str, float]:
        """Root mean square of every column, by name."""
    def to_pandas(self) -> Any:
        """A pandas DataFrame indexed by time (needs pandas)."""

class Take:
    """A loaded take."""
    @property
    def path(self) -> str: ...
    @property
    def frames(self) -> int: ...
    @property
    def time(self) -> npt.NDArray[np.float64]: ...
    @property
    def coordinates(self) -> list[str]: ...
    @property
    def notes(self) -> list[str]: ...
    def info(self) -> dict[str, Any]:
        """`articula info --json` as a dict."""
    def inverse_dynamics(self, *, consistent: Optional[str] = ...) -> Result:
        """`articula id`: torques, with ground reactions when the take has contact."""
    def anatomy(self, *, consistent: Optional[str] = ...) -> Result:
        """`articula anatomy`: anatomical angles (deg) and moments (N·m, N·m/kg)."""
    def simulate(
        self,
        *,
        integrator: str = ...,
        dt: float = ...,
        kp: Optional[_Repeated] = ...,
        kv: Optional[_Repeated] = ...,
        mass_error: float = ...,
        duration: Optional[float] = ...,
    ) -> Result:
        """`articula simulate`: computed-torque tracking of the take."""
    def export(
        self,
        path: _Path,
        what: str = ...,
        *,
        format: Optional[str] = ...,
        trc_units: Optional[str] = ...,
    ) -> Optional[Result]:
        """`articula export WHAT`: writes the file; its table when a CSV table."""

class Model:
    """A robot model; every method takes one state (1-D) or one state per row (2-D)."""
    @staticmethod
    def from_urdf(
        path: _Path, *, floating: bool = ..., gravity: Optional[Sequence[float]] = ...
    ) -> Model: ...
    @property
    def nq(self) -> int: ...
    @property
    def nv(self) -> int: ...
    @property
    def q_names(self) -> list[str]: ...
    @property
    def v_names(self) -> list[str]: ...
    def rnea(self, q: _Array, v: _Array, a: _Array) -> npt.NDArray[np.float64]:
        """Inverse dynamics: τ = M(q) a + h(q, v)."""
    def crba(self, q: _Array) -> npt.NDArray[np.float64]:
        """The mass matrix M(q), nv × nv per row."""
    def aba(self, q: _Array, v: _Array, tau: _Array) -> npt.NDArray[np.float64]:
        """Forward dynamics: a = M(q)⁻¹ (τ − h(q, v))."""
