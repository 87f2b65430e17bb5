"""The results of compare, fit, sweep and diagnose: the CLI's JSON (docs/formats.md) as
objects with typed attributes, ``to_dict()`` and ``to_frame()`` (pandas)."""

from __future__ import annotations

import copy
import io
import json
from collections.abc import Mapping
from typing import Any


def _pandas():
    try:
        import pandas
    except ImportError as e:  # pragma: no cover - the message is the point
        raise ImportError(
            "to_frame() needs pandas: pip install pandas (or softgrip[pandas])"
        ) from e
    return pandas


class Result(Mapping):
    """The CLI's JSON of one result, read as a mapping (``r["nrmse"]``) or by attribute."""

    def __init__(self, data: dict[str, Any]):
        self._data = data

    @classmethod
    def from_json(cls, text: str):
        return cls(json.loads(text))

    def __getitem__(self, key: str) -> Any:
        return self._data[key]

    def __iter__(self):
        return iter(self._data)

    def __len__(self) -> int:
        return len(self._data)

    def to_dict(self) -> dict[str, Any]:
        """A deep copy of the JSON, as ``--json`` writes it."""
        return copy.deepcopy(self._data)

    def to_frame(self):
        """One row: the top-level numbers and strings, and ``params`` as ``param.NAME``."""
        row = {k: v for k, v in self._data.items() if isinstance(v, (int, float, str, bool))}
        for name, value in (self._data.get("params") or {}).items():
            row[f"param.{name}"] = value
        return _pandas().DataFrame([row])

    def __repr__(self) -> str:
        return f"{type(self).__name__}({json.dumps(self._data)[:200]})"


class CompareResult(Result):
    """``softgrip compare --json``: the replay's error against the recording."""

    @property
    def nrmse(self) -> float:
        """RMSE over the object markers over the object's largest extent (thesis eq. 45-46)."""
        return self._data["nrmse"]

    @property
    def rmse_m(self) -> float:
        return self._data["rmse_m"]

    @property
    def nrmse_all(self) -> float:
        """The same over every marker, fingers included."""
        return self._data["nrmse_all"]

    @property
    def rmse_all_m(self) -> float:
        return self._data["rmse_all_m"]

    @property
    def observations(self) -> int:
        return self._data["observations"]

    @property
    def params(self) -> dict[str, float | None]:
        return dict(self._data.get("params") or {})


class FitResult(CompareResult):
    """``softgrip fit --json``: the fitted parameters, their standard errors and identifiability,
    the error before and after."""

    @property
    def start(self) -> dict[str, float | None]:
        return dict(self._data["start"])

    @property
    def standard_errors(self) -> dict[str, float | None]:
        return dict(self._data["standard_errors"])

    @property
    def identifiability(self) -> dict[str, str]:
        return dict(self._data["identifiability"])

    @property
    def before(self) -> dict[str, float]:
        return dict(self._data["before"])

    @property
    def converged(self) -> bool:
        return self._data["converged"]

    def to_frame(self):
        """One row per parameter: start, fitted, standard error, identifiability."""
        rows = [
            {
                "param": name,
                "start": self.start.get(name),
                "fitted": value,
                "standard_error": self.standard_errors.get(name),
                "identifiability": self.identifiability.get(name),
            }
            for name, value in self.params.items()
        ]
        return _pandas().DataFrame(rows)


class SweepResult(CompareResult):
    """``softgrip sweep --json`` (the best point) with every point (``--csv``): ``csv`` and
    ``json`` are the texts the CLI writes, byte for byte."""

    def __init__(self, data: dict[str, Any], csv: str, json_text: str):
        super().__init__(data)
        self.csv = csv
        self.json = json_text

    @classmethod
    def from_outputs(cls, csv: str, json_text: str) -> SweepResult:
        return cls(json.loads(json_text), csv, json_text)

    @property
    def points(self) -> int:
        return self._data["points"]

    @property
    def failed(self) -> int:
        return self._data["failed"]

    def to_frame(self):
        """Every point: one column per parameter, nrmse, rmse_m, nrmse_all, rmse_all_m, error."""
        return _pandas().read_csv(io.StringIO(self.csv))


class Diagnosis(Result):
    """``softgrip diagnose --json``: the verdict, its evidence and every candidate fitted."""

    @property
    def verdict(self) -> str:
        """The first effect named, "none" or "unexplained" (every effect: :attr:`effects`)."""
        return self._data["verdict"]["effect"]

    @property
    def effects(self) -> list[str]:
        """Every effect named, in the order found; empty for "none" and "unexplained"."""
        return list(self._data["verdict"].get("effects", []))

    @property
    def evidence(self) -> str:
        return self._data["verdict"].get("evidence", "")

    @property
    def params(self) -> dict[str, float]:
        """The final model's fitted values."""
        return dict(self._data["verdict"].get("params") or {})

    @property
    def standard_errors(self) -> dict[str, float | None]:
        return dict(self._data["verdict"].get("standard_errors") or {})

    @property
    def alternatives(self) -> list[dict[str, Any]]:
        """Readings that fit about as well (Vuong's test does not find them worse)."""
        return list(self._data["verdict"].get("alternatives", []))

    @property
    def set_aside(self) -> list[str]:
        """Effects the search named that the checks of what the final model leaves set aside
        (the verdict is then "unexplained")."""
        return list(self._data["verdict"].get("set_aside", []))

    @property
    def unexplained_at(self) -> list[str]:
        """The markers where the final model leaves a mismatch it has no model of (empty when the
        checks pass): see ``verdict.remainder`` in the JSON."""
        return list((self._data["verdict"].get("remainder") or {}).get("markers", []))

    @property
    def model(self) -> str:
        """The model fitted: "continuum" or "lattice"."""
        return self._data["baseline"]["model"]

    def to_frame(self):
        """One row per candidate fitted: effect, variant, round, change of BIC, share explained,
        Vuong's z, NRMSE after."""
        rows = [
            {
                "effect": h.get("effect"),
                "variant": h.get("variant", ""),
                "round": h.get("round"),
                "score": h.get("score"),
                "explained": h.get("explained"),
                "vuong_z": h.get("vuong_z"),
                "nrmse": h.get("nrmse"),
                "named": h.get("effect") in self.effects,
            }
            for h in self._data.get("hypotheses", [])
        ]
        return _pandas().DataFrame(rows)


class GraspWindow(Result):
    """``softgrip grasp window --json``: the least squeeze that holds, the most before damage and
    every squeeze tried."""

    @property
    def least_squeeze(self) -> float:
        """The least squeeze per finger that lifts and holds the object (N)."""
        return self._data["least_squeeze"]

    @property
    def most_squeeze(self) -> float | None:
        """The most before the damage measure reaches its limit (N); None where not reached."""
        return self._data["most_squeeze"]

    @property
    def window(self) -> bool:
        """Whether some squeeze both holds and stays below the limit."""
        return self._data["window"]

    @property
    def curves(self) -> dict[str, Any]:
        """The squeezes tried as numpy arrays: ``squeeze`` (N), ``held``, ``margin`` (the slip
        margin, 1 - load / friction capacity) and ``peak`` (the damage measure's largest value)."""
        import numpy as np

        samples = self._data["samples"]
        return {
            "squeeze": np.array([s["squeeze"] for s in samples]),
            "held": np.array([s["held"] for s in samples]),
            "margin": np.array([s["margin"] for s in samples]),
            "peak": np.array([s["peak"]["value"] for s in samples]),
        }

    def to_frame(self):
        """One row per squeeze tried: squeeze, held, slip_m, margin, peak."""
        rows = [
            {
                "squeeze": s["squeeze"],
                "held": s["held"],
                "slip_m": s["slip_m"],
                "margin": s["margin"],
                "peak": s["peak"]["value"],
            }
            for s in self._data["samples"]
        ]
        return _pandas().DataFrame(rows)
