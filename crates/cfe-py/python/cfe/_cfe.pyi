"""Type hints of the native module `cfe._cfe` (Rust, PyO3). Use the `cfe` package's
API (`cfe.Model`, `cfe.Mesh`, `cfe.Results`); these are its building blocks."""

from os import PathLike
from typing import Any, Callable, Dict, List, Mapping, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

class CfeError(Exception):
    """Any error of cfe; the message names the file, line, key, part or node at fault."""

class ParseError(CfeError):
    """The problem cannot be read (file, TOML, unknown key, unknown name, a name
    given twice: then also ``key``, e.g. ``interface#2.name``, and ``name``)."""

    path: Optional[Union[str, PathLike[str]]]
    line: Optional[int]

class ModelError(CfeError):
    """An invalid model (settings, materials)."""

    part: str
    key: str

class MeshError(CfeError):
    """An unusable mesh: bad arrays, inverted or degenerate elements, bad boundaries."""

    part: str

class CouplingError(CfeError):
    """An interface cannot be built (coupling nodes on no host edge, no pair
    within ``search_distance``: then ``search_distance`` and ``nearest``)."""

    interface: str
    nodes: List[Tuple[int, Tuple[float, float]]]

class SingularError(CfeError):
    """A singular system: a part without support, a mechanism."""

    parts: List[str]
    increment: int
    part: str
    node: int
    component: int

class ConvergenceError(CfeError):
    """The contact iteration did not converge."""

class LawViolationError(CfeError):
    """No consistent contact state, and the least-violating one breaks the law by more than `[analysis] max_violation`."""

    increment: int
    pairs: List[Tuple[str, int]]

class PrecisionError(CfeError):
    """The solution lost accuracy (out-of-balance force above `[analysis] max_residual`); typically a penalty far above E·t."""

    increment: int
    residual: float

class TooLargeError(CfeError):
    """The model would need more memory than the machine has; refused before meshing."""

    unknowns: int
    bytes: int
    available: int

class OutputError(CfeError):
    """A result file cannot be written, or the output folder is refused: it holds
    files cfe did not write where it would write (`files`), something cfe cannot
    write through (`files`), or another run writes into it (`pid`)."""

    path: Union[str, PathLike[str]]
    files: List[Union[str, PathLike[str]]]
    pid: Optional[int]

class Mesh:
    """A part's mesh from arrays, checked (see `cfe.Mesh`)."""

    def __init__(
        self,
        points: npt.NDArray[np.float64],
        triangles: Optional[npt.NDArray[np.int64]] = None,
        quads: Optional[npt.NDArray[np.int64]] = None,
        boundaries: Optional[Dict[str, Union[npt.NDArray[np.int64], List[npt.NDArray[np.int64]]]]] = None,
        *,
        tetrahedra: Optional[npt.NDArray[np.int64]] = None,
        hexahedra: Optional[npt.NDArray[np.int64]] = None,
        part: str = "mesh",
    ) -> None: ...
    @property
    def dimension(self) -> int: ...
    @property
    def points(self) -> npt.NDArray[np.float64]: ...
    @property
    def triangles(self) -> npt.NDArray[np.int64]: ...
    @property
    def quads(self) -> npt.NDArray[np.int64]: ...
    @property
    def tetrahedra(self) -> npt.NDArray[np.int64]: ...
    @property
    def hexahedra(self) -> npt.NDArray[np.int64]: ...
    @property
    def boundaries(self) -> Dict[str, npt.NDArray[np.int64]]: ...

class Model:
    """A checked, meshed model (see `cfe.Model`)."""

    @staticmethod
    def from_file(path: Union[str, PathLike[str]], refine: int = 1) -> Model: ...
    @staticmethod
    def from_inp(path: Union[str, PathLike[str]]) -> Model: ...
    @property
    def dimension(self) -> int: ...
    @property
    def notes(self) -> List[str]: ...
    @staticmethod
    def from_toml(
        text: str,
        refine: int = 1,
        path: Optional[Union[str, PathLike[str]]] = None,
        meshes: Optional[Mapping[str, Mesh]] = None,
    ) -> Model: ...
    @property
    def title(self) -> str: ...
    @property
    def refine(self) -> int: ...
    @property
    def text(self) -> str: ...
    @property
    def parts(self) -> List[str]: ...
    @property
    def interfaces(self) -> List[str]: ...
    @property
    def settings(self) -> Dict[str, Any]: ...
    @property
    def steps(self) -> List[Dict[str, Any]]: ...
    def mesh(self, name: str) -> Mesh: ...
    def check(self) -> str: ...
    def solve(
        self,
        progress: Optional[Callable[[Dict[str, Any]], Any]] = None,
        out: Optional[Union[str, PathLike[str]]] = None,
        law: Optional[str] = None,
        friction: Optional[float] = None,
        write_every: Optional[Union[int, str]] = None,
        force: bool = False,
    ) -> Dict[str, Any]:
        """Solves with the GIL released; the raw results: `u`, `parts`, `interfaces`,
        `summary`, `load_factor`, `step`, `time`, `dimension`."""

def dict_to_toml(problem: Mapping[str, Any]) -> str:
    """The TOML text of a problem given as dicts and lists (None leaves a key out)."""
