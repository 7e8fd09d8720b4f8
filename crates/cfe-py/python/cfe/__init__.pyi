"""Type hints of the `cfe` package (the implementation and its docstrings are in
`__init__.py`)."""

from dataclasses import dataclass
from os import PathLike
from typing import Any, Callable, Dict, List, Mapping, NamedTuple, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

from ._cfe import (
    CfeError as CfeError,
    ConvergenceError as ConvergenceError,
    CouplingError as CouplingError,
    LawViolationError as LawViolationError,
    MeshError as MeshError,
    ModelError as ModelError,
    OutputError as OutputError,
    ParseError as ParseError,
    PrecisionError as PrecisionError,
    SingularError as SingularError,
    TooLargeError as TooLargeError,
)

__version__: str
_Path = Union[str, PathLike[str]]
_Floats = npt.NDArray[np.float64]
_Ints = npt.NDArray[np.int64]

class Increment(NamedTuple):
    """What a progress callback receives after each converged increment."""

    increment: int
    increments: int
    load_factor: float
    iterations: int
    step: str = "step-1"
    time: float = 0.0
    history: Optional[Dict[str, Any]] = None

class Mesh:
    """A part's mesh given as arrays, checked by the library."""

    def __init__(
        self,
        points: npt.ArrayLike,
        triangles: Optional[npt.ArrayLike] = None,
        quads: Optional[npt.ArrayLike] = None,
        boundaries: Optional[Mapping[str, Union[npt.ArrayLike, Sequence[npt.ArrayLike]]]] = None,
        *,
        tetrahedra: Optional[npt.ArrayLike] = None,
        hexahedra: Optional[npt.ArrayLike] = None,
        part: str = "mesh",
    ) -> None: ...
    @property
    def dimension(self) -> int: ...
    @property
    def points(self) -> _Floats: ...
    @property
    def triangles(self) -> _Ints: ...
    @property
    def quads(self) -> _Ints: ...
    @property
    def tetrahedra(self) -> _Ints: ...
    @property
    def hexahedra(self) -> _Ints: ...
    @property
    def boundaries(self) -> Dict[str, _Ints]: ...
    def boundary_nodes(self, name: str) -> _Ints: ...
    @classmethod
    def from_meshio(
        cls,
        mesh: Any,
        *,
        surfaces: Optional[Sequence[Union[str, int]]] = None,
        volumes: Optional[Sequence[Union[str, int]]] = None,
        part: str = "mesh",
    ) -> Mesh: ...
    def to_meshio(self) -> Any: ...

class Model:
    """A checked, meshed model, ready to solve."""

    def __init__(self, problem: Mapping[str, Any], *, refine: int = 1, path: Optional[_Path] = None) -> None: ...
    @classmethod
    def from_dict(cls, problem: Mapping[str, Any], *, refine: int = 1, path: Optional[_Path] = None) -> Model: ...
    @classmethod
    def from_file(cls, path: _Path, *, refine: int = 1) -> Model: ...
    @classmethod
    def from_inp(cls, path: _Path) -> Model: ...
    @property
    def notes(self) -> List[str]: ...
    @property
    def dimension(self) -> int: ...
    @classmethod
    def from_toml(
        cls,
        text: str,
        *,
        refine: int = 1,
        path: Optional[_Path] = None,
        meshes: Optional[Mapping[str, Any]] = None,
    ) -> Model: ...
    @property
    def title(self) -> str: ...
    @property
    def parts(self) -> List[str]: ...
    @property
    def interfaces(self) -> List[str]: ...
    @property
    def settings(self) -> Dict[str, Any]: ...
    @property
    def steps(self) -> List[Dict[str, Any]]: ...
    @property
    def refine(self) -> int: ...
    @property
    def text(self) -> str: ...
    def mesh(self, part: str) -> Mesh: ...
    def check(self) -> str: ...
    def solve(
        self,
        progress: Optional[Callable[[Increment], Any]] = None,
        *,
        out: Optional[_Path] = None,
        law: Optional[str] = None,
        friction: Optional[float] = None,
        write_every: Optional[Union[int, str]] = None,
        force: bool = False,
    ) -> Results: ...

def run(
    problem: Union[_Path, str, Mapping[str, Any], Model],
    *,
    refine: int = 1,
    progress: Optional[Callable[[Increment], Any]] = None,
    out: Optional[_Path] = None,
    law: Optional[str] = None,
    friction: Optional[float] = None,
    write_every: Optional[Union[int, str]] = None,
    force: bool = False,
) -> Results: ...

@dataclass
class PartResult:
    name: str
    points: _Floats
    triangles: _Ints
    triangle_ids: _Ints
    quads: _Ints
    quad_ids: _Ints
    boundaries: Dict[str, _Ints]
    material: Dict[str, float]
    displacement: _Floats
    stress: _Floats
    element_stress: _Floats
    von_mises: _Floats
    element_von_mises: _Floats
    sigma_theta: Optional[_Floats] = None
    element_sigma_theta: Optional[_Floats] = None
    tetrahedra: Optional[_Ints] = None
    tetrahedron_ids: Optional[_Ints] = None
    hexahedra: Optional[_Ints] = None
    hexahedron_ids: Optional[_Ints] = None
    @property
    def dimension(self) -> int: ...
    @property
    def sigma_xx(self) -> _Floats: ...
    @property
    def sigma_yy(self) -> _Floats: ...
    @property
    def sigma_xy(self) -> _Floats: ...
    @property
    def sigma_zz(self) -> _Floats: ...
    @property
    def sigma_yz(self) -> _Floats: ...
    @property
    def sigma_xz(self) -> _Floats: ...
    @property
    def ux(self) -> _Floats: ...
    @property
    def uy(self) -> _Floats: ...
    @property
    def uz(self) -> _Floats: ...
    def boundary_nodes(self, name: str) -> _Ints: ...
    def to_meshio(self) -> Any: ...

@dataclass
class InterfaceResult:
    name: str
    host: str
    node_part: str
    law: str
    c_n: float
    c_s: float
    node: _Ints
    host_element: _Ints
    position: _Floats
    normal: _Floats
    bonded: npt.NDArray[np.bool_]
    settled: npt.NDArray[np.bool_]
    gap_n: _Floats
    slip_s: _Floats
    force_n: _Floats
    force_s: _Floats
    violation: npt.NDArray[np.int32]
    violation_amount: _Floats
    friction: float
    unpaired: int
    gap0: _Floats
    gap: _Floats
    slip: _Floats
    pressure: _Floats
    shear: _Floats
    tributary: _Floats
    slip_t2: Optional[_Floats] = None
    force_t2: Optional[_Floats] = None
    slip_t2_plastic: Optional[_Floats] = None
    shear_t2: Optional[_Floats] = None
    force: Optional[_Floats] = None
    t1: Optional[_Floats] = None
    t2: Optional[_Floats] = None
    extra: Dict[str, npt.NDArray[Any]] = ...
    @property
    def x(self) -> _Floats: ...
    @property
    def y(self) -> _Floats: ...
    @property
    def z(self) -> _Floats: ...
    @property
    def state(self) -> npt.NDArray[np.str_]: ...
    def __len__(self) -> int: ...

class Results:
    summary: Dict[str, Any]
    load_factor: float
    step: str
    time: float
    displacements: _Floats
    dimension: int
    parts: Dict[str, PartResult]
    interfaces: Dict[str, InterfaceResult]
    reactions: Dict[str, _Floats]
    history: Dict[str, Any]
    lines: Dict[str, Dict[str, Any]]
    def __init__(self, raw: Dict[str, Any], model: Model, law: Optional[str] = None) -> None: ...
    @property
    def status(self) -> str: ...
    @property
    def max_displacement(self) -> Dict[str, Any]: ...
    def to_meshio(self, part: Optional[str] = None) -> Any: ...
    def write(self, folder: _Path, *, force: bool = False) -> Dict[str, Any]: ...
