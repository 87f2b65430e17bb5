"""Lab recordings (docs/recordings.md): read from their files or made from a pandas frame in
the spec's long format (one row per marker and sample: time, load, marker, x, y, z)."""

from __future__ import annotations

import math
import tempfile
from pathlib import Path
from typing import Any

from . import _softgrip
from ._softgrip import Scene

COLUMNS = ["time", "load", "marker", "x", "y", "z"]


class Recording:
    """A lab recording: its scene, markers and samples."""

    def __init__(self, inner: _softgrip.Recording):
        self._inner = inner

    @classmethod
    def load(cls, path: str | Path) -> Recording:
        """The recording file (``recording.toml``) with its scene and samples."""
        return cls(_softgrip.Recording.load(str(path)))

    @classmethod
    def from_frame(
        cls,
        frame: Any,
        scene: Scene,
        markers: dict[str, tuple[float, float, float]],
        mode: str = "quasi-static",
        start: str | None = None,
        description: str = "",
        directory: str | Path | None = None,
    ) -> Recording:
        """A recording from a pandas DataFrame in the long format: columns ``load``, ``marker``,
        ``x``, ``y``, ``z`` and, for a time series, ``time`` (s); a coordinate not observed is
        NaN or the column is left out. ``markers`` gives each object marker's point on the
        undeformed surface (m); ``finger`` (``finger1``, ...) is the finger's centre.
        ``mode`` is "quasi-static" or "time-series", ``start`` ("rest" or "equilibrium") where a
        time series starts. The files are written to ``directory`` (kept) or a temporary one,
        and read back with the same checks as :meth:`load`."""
        missing = [c for c in ("load", "marker") if c not in frame.columns]
        if missing:
            raise _softgrip.SoftgripError(
                f"from_frame: the frame has no column {', '.join(missing)}; "
                f"the long format's columns are {', '.join(COLUMNS)}"
            )
        table = frame.copy()
        for c in COLUMNS:
            if c not in table.columns:
                table[c] = float("nan")
        table = table[COLUMNS]
        lines = [",".join(COLUMNS)]
        for row in table.itertuples(index=False):
            cells = [_number(row.time), _number(row.load), str(row.marker)]
            cells += [_number(v) for v in (row.x, row.y, row.z)]
            lines.append(",".join(cells))
        header = [
            'scene = "scene.toml"',
            'samples = "samples.csv"',
            f'mode = "{mode}"',
        ]
        if start is not None:
            header.append(f'start = "{start}"')
        if description:
            header.append("description = " + _toml_string(description))
        header.append("")
        header.append("[markers]")
        for name, point in markers.items():
            x, y, z = (float(v) for v in point)
            header.append(f"{_toml_key(name)} = [{x!r}, {y!r}, {z!r}]")

        def write(d: Path) -> Recording:
            (d / "scene.toml").write_text(scene.to_toml())
            (d / "samples.csv").write_text("\n".join(lines) + "\n")
            (d / "recording.toml").write_text("\n".join(header) + "\n")
            return cls.load(d / "recording.toml")

        if directory is not None:
            d = Path(directory)
            d.mkdir(parents=True, exist_ok=True)
            return write(d)
        with tempfile.TemporaryDirectory(prefix="softgrip-recording-") as d:
            return write(Path(d))

    @property
    def path(self) -> str:
        return self._inner.path

    @property
    def mode(self) -> str:
        """"quasi-static" or "time-series"."""
        return self._inner.mode

    @property
    def description(self) -> str:
        return self._inner.description

    @property
    def scene(self) -> Scene:
        """A copy of the recording's scene."""
        return self._inner.scene

    @property
    def markers(self) -> dict[str, tuple[float, float, float]]:
        """The object markers: name to reference point (m)."""
        return dict(self._inner.markers)

    def to_frame(self):
        """The samples in the long format (time NaN in quasi-static mode; NaN where an axis
        was not observed)."""
        import pandas

        return pandas.DataFrame(self._inner.columns())[COLUMNS]

    def __len__(self) -> int:
        return len(self._inner)

    def __repr__(self) -> str:
        return repr(self._inner)


def _number(v: Any) -> str:
    if v is None:
        return ""
    v = float(v)
    return "" if math.isnan(v) else repr(v)


def _toml_string(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def _toml_key(name: str) -> str:
    bare = name.replace("_", "").replace("-", "").isalnum()
    return name if bare else _toml_string(name)
