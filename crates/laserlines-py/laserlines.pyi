"""Line segments from 2D laser range scans (the Rust library laserlines).

Units are SI (metres, radians); frames follow REP 103 (x forward, y left, angles
counter-clockwise). Beam ``i`` points at ``angle_min + i * angle_increment``; a range that is
NaN, inf, not positive or outside ``range_min..range_max`` is "no return".

Lines come as a numpy structured array, one record per line (``lines["r"]`` is the column of
``r``, ``lines["start"]`` an (n, 2) array, ``lines[i]`` the i-th line); its fields:

- ``start``, ``end``: (n, 2) float64, end points in the laser frame, m (``start`` at beam
  ``first``);
- ``r``: (n,) float64, distance of the line from the laser, m; ``alpha``: (n,) float64, the
  direction of its normal, rad, in (-pi, pi] (the line is ``x cos(alpha) + y sin(alpha) = r``);
- ``first``, ``last``: (n,) int64, the first and last supporting beam (inclusive; a line of
  ``hough-split`` across the seam of a 360 deg scan has ``first > last``: beams ``first..n``,
  then ``0..=last``);
  ``points``: (n,) int64, the number of supporting points;
- ``rms``: (n,) float64, RMS orthogonal residual, m;
- ``covariance``: (n, 2, 2) float64, covariance of (r, alpha): [[m², m rad], [m rad, rad²]].
"""

from os import PathLike
from typing import Any, Dict, Iterator, Optional, Sequence, Tuple, Union, final

import numpy as np
import numpy.typing as npt

__version__: str

ALGORITHMS: Tuple[str, ...]
"""The extractors by name, the paper's ``hough-split`` first."""

# Aliases for this stub's annotations only (the module has no such names).
_Lines = npt.NDArray[np.void]
"""The lines of one scan, a structured array with the fields ``start``, ``end``, ``r``,
``alpha``, ``first``, ``last``, ``points``, ``rms``, ``covariance`` (see the module
docstring)."""

_Ranges = Union[npt.NDArray[np.float64], npt.NDArray[np.float32]]
"""Ranges of one scan, m: a 1-D float64 array (read in place when contiguous) or float32."""

_Path = Union[str, bytes, "PathLike[str]", "PathLike[bytes]"]
"""A file path, as ``open()`` takes one."""

_Pose = Union[Tuple[float, float, float], Sequence[float], npt.NDArray[np.float64]]
"""A pose (x, y, theta) in m, m, rad: any sequence of three numbers."""

@final
class Scan:
    """One laser scan, shaped like ``sensor_msgs/LaserScan``."""

    def __init__(
        self,
        ranges: _Ranges,
        angle_min: float,
        angle_increment: float,
        range_min: float = 0.0,
        range_max: float = float("inf"),
        stamp: Optional[float] = None,
        pose: Optional[_Pose] = None,
        odometry: Optional[_Pose] = None,
    ) -> None:
        """A scan; ``range_max=inf`` means no upper limit. ValueError for broken geometry,
        or a ``stamp``, ``pose`` or ``odometry`` that is not finite.

        A float64 ``ranges`` array is kept as it is, not copied: writing to it later changes
        the scan (``ranges.copy()`` gives one of its own); other arrays are kept as their
        float64 copy."""
    @property
    def ranges(self) -> npt.NDArray[np.float64]:
        """The ranges, m."""
    @property
    def intensities(self) -> Optional[npt.NDArray[np.float64]]:
        """The intensities, one per range, when the source has them."""
    @property
    def angle_min(self) -> float:
        """Angle of the first beam, rad."""
    @property
    def angle_increment(self) -> float:
        """Angle between beams, rad (negative: a clockwise scan)."""
    @property
    def range_min(self) -> float:
        """Smallest valid range, m."""
    @property
    def range_max(self) -> float:
        """Largest valid range, m (``inf``: no limit)."""
    @property
    def stamp(self) -> Optional[float]:
        """Time stamp, s, when the source has one."""
    @property
    def pose(self) -> Optional[Tuple[float, float, float]]:
        """The robot's pose (x, y, theta) in m, m, rad, when the source has one."""
    @property
    def odometry(self) -> Optional[Tuple[float, float, float]]:
        """The wheel odometry's pose (x, y, theta) in m, m, rad at the scan, when the source
        has it."""
    def __len__(self) -> int: ...

@final
class ScanIterator(Iterator[Scan]):
    """The scans of a file, in file order (see :func:`read`)."""

    def __iter__(self) -> "ScanIterator": ...
    def __next__(self) -> Scan: ...
    @property
    def skipped(self) -> int:
        """Records skipped so far (with ``skip_bad=True``)."""
    @property
    def skip_reasons(self) -> Dict[str, int]:
        """What the reader left out so far, by reason, as the command line's summary lists
        it: bad records skipped (``malformed record``), scans of other topics, readings
        sharing a beam, scans of a chunk or row group that could not be read, ..."""

@final
class Extractor:
    """A line extractor chosen by name (one of :data:`ALGORITHMS`), with its parameters as
    keyword arguments laid over the algorithm's defaults, exactly as a ``[name]`` table of a
    ``laserlines --params`` file: nested parameters as dicts (``breakpoints={"noise": 0.02}``),
    a preset by name for hough-split (``paper=True``, ``complete=True``, ``navigation=True``,
    ``walls=True``), ``noise="auto"``, a preset name such as ``"urg-04lx"`` or
    ``{"sigma_min": 0.01, "fraction": 0.01}`` for hough-split. An unknown algorithm or
    parameter, or a value of the wrong type or out of range, raises ValueError naming it.

    The extractor keeps its working memory between calls. The GIL is released while it
    extracts: threads with one extractor each run in parallel (calls on one extractor from
    several threads take turns).
    """

    def __init__(self, algorithm: str = "hough-split", **params: Any) -> None: ...
    @property
    def algorithm(self) -> str:
        """The algorithm's name."""
    def __reduce__(self) -> Tuple[Any, Tuple[()]]:
        """Pickling (``pickle``, ``copy``, a Ray task's closure): an extractor of the same
        algorithm and parameters, with fresh working memory."""
    @property
    def params(self) -> Dict[str, Any]:
        """Every parameter the extractor runs with (SI units, angles in radians), as a
        params file writes them: one left unset (``range_limits``: the scan's own) is absent."""
    @property
    def last_ranges_address(self) -> int:
        """Address of the first range the last extraction read: ``ranges.ctypes.data`` when a
        contiguous float64 array was read in place."""
    def extract(
        self,
        ranges: Union[_Ranges, Scan],
        angle_min: Optional[float] = None,
        angle_increment: Optional[float] = None,
        range_min: Optional[float] = None,
        range_max: Optional[float] = None,
    ) -> _Lines:
        """The lines of one scan: ranges with their geometry, or a :class:`Scan` (which brings
        its own geometry and range limits: giving any of the four with it is a TypeError).

        A contiguous float64 array is read where it is, without a copy (do not write to it
        from another thread meanwhile); float32, other float types, other-endian and strided
        arrays are converted. ``range_min`` defaults to 0, ``range_max`` to ``inf`` (no upper limit).
        TypeError for anything but a numpy array of floats (a masked array too: its mask would
        be lost; ``numpy.ma.filled(ranges, numpy.nan)`` makes masked beams no return),
        ValueError for an array that is not 1-D, an ``angle_increment`` that is zero or not
        finite, limits out of order (a negative increment is a clockwise scan, not an
        error)."""
    def time_extract(
        self,
        ranges: _Ranges,
        angle_min: float,
        angle_increment: float,
        range_min: float = 0.0,
        range_max: float = float("inf"),
        repeat: int = 1000,
    ) -> float:
        """Seconds per extraction of one scan, timed in Rust around the extraction alone (the
        mean of ``repeat``, 1 or more: 0 or less is a ValueError): a call of :meth:`extract`
        costs this plus the binding's overhead."""
    def extract_table(self, table: Any) -> Any:
        """The lines (a ``pyarrow.Table`` of :func:`lines_schema`, one row per line) of a table
        of scans in :func:`scans_schema` (a ``pyarrow.Table``, a ``RecordBatchReader`` or
        anything with ``__arrow_c_stream__``; ``convert LOG scans.parquet`` writes one, and a
        Ray Data batch of it is one). Scans keep the table's ``scan`` index (else their row)."""
    def extract_messages(self, table: Any) -> Any:
        """The lines (a ``pyarrow.Table`` of :func:`lines_schema`) of a table of LaserScan
        messages, one per row, as Ray Data's ``read_mcap(..., include_metadata=True)`` gives
        them (``data``, ``schema_name``, ``message_encoding``, ``log_time`` in ns); scans
        are numbered by row. Decoded and extracted at full precision (unlike a detour
        through :func:`scans_from_messages`, whose table holds float32 ranges)."""
    def extract_file(
        self,
        path: _Path,
        topic: Optional[str] = None,
        skip_bad: bool = False,
        format: Optional[str] = None,
    ) -> Any:
        """The lines of every scan of a file (any format ``laserlines extract`` reads; by its
        name, or ``format`` as ``extract --format`` takes it) as a ``pyarrow.Table`` of
        :func:`lines_schema`."""

def extract(
    ranges: Union[_Ranges, Scan],
    angle_min: Optional[float] = None,
    angle_increment: Optional[float] = None,
    range_min: Optional[float] = None,
    range_max: Optional[float] = None,
    algorithm: str = "hough-split",
    **params: Any,
) -> _Lines:
    """The lines of one scan with a new :class:`Extractor` of ``algorithm`` and ``params``
    (use an :class:`Extractor` for many scans: it keeps its working memory); the arguments
    as :meth:`Extractor.extract` takes them."""

def scan_from_bearings(
    bearings: npt.ArrayLike,
    ranges: npt.ArrayLike,
    angle_increment: Optional[float] = None,
    range_min: float = 0.0,
    range_max: float = float("inf"),
) -> Tuple[Scan, int]:
    """Readings at their own bearings (a spinning scanner's raw output, RPLIDAR or YDLIDAR:
    bearings not evenly spaced) as a :class:`Scan` of evenly spaced beams, and the number of
    readings left out. Bearings in radians, counter-clockwise (REP 103; the RPLIDAR SDK's
    clockwise degrees: ``-np.radians(theta)``), any turn; ranges in metres. Each reading goes
    to the beam nearest its bearing; the spacing is the bearings' median spacing, or
    ``angle_increment``. Readings that leave no gap wider than 4 spacings make a full turn,
    others a sector that starts after its widest gap; a beam without a reading is NaN. Two
    readings on one beam keep a measurement (above 0, inside the limits), then the nearer; the
    other is counted in the returned number. Lengths that differ, a bearing that is not
    finite, or a spacing that cannot be told raise ValueError."""

def read(
    path: _Path,
    topic: Optional[str] = None,
    skip_bad: bool = False,
    format: Optional[str] = None,
) -> ScanIterator:
    """The scans of a file, with stamps and poses: every format ``laserlines extract`` reads
    (MCAP and ROS 2 bag directories, Parquet scans tables, BreezySLAM ``.dat``, CARMEN logs,
    ROS 1 bags, JSON, JSONL, CSV; ``.gz`` inflated), told by the file's name or by ``format``
    (``json``, ``jsonl``, ``csv``, ``dat``, ``mcap``, ``carmen``, ``bag``, ``db3``,
    ``parquet``; an unknown name is a ValueError). ``topic`` picks a topic (MCAP, bags) or a
    laser (CARMEN). A bad record raises ValueError naming the file and line (or byte offset or
    row); ``skip_bad=True`` skips and counts it. A failed read of the file itself (an I/O
    error, a corrupt gzip stream) raises OSError, with ``skip_bad=True`` too. A missing file
    raises FileNotFoundError."""

def extract_file(
    path: _Path,
    topic: Optional[str] = None,
    algorithm: str = "hough-split",
    skip_bad: bool = False,
    format: Optional[str] = None,
    **params: Any,
) -> Any:
    """The lines of every scan of a file as a ``pyarrow.Table`` of :func:`lines_schema`: one
    row per line, with the scan's index (from 0, in file order), stamp and pose."""

def lines_schema() -> Any:
    """The ``pyarrow.Schema`` of lines tables (``extract -o lines.parquet``)."""

def scans_schema() -> Any:
    """The ``pyarrow.Schema`` of scans tables (``convert LOG scans.parquet``)."""

def scans_from_messages(table: Any) -> Any:
    """LaserScan messages one per row, as Ray Data's ``read_mcap(..., include_metadata=True)``
    gives them (``data``, ``schema_name``, ``message_encoding``, ``log_time`` in ns), as a
    ``pyarrow.Table`` of :func:`scans_schema`. ValueError names a row that is not a LaserScan
    or does not decode."""
