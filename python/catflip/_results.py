"""What the commands return: the CLI's JSON report as a dict, and the schedule's time series as
numpy arrays, read from the very schedule file the CLI exports (README, "Replay elsewhere").

Conventions: SI units; ``q = (q1, q2)`` with ``R_AB = Rx(q1) · Ry(q2)``; torques are the motor
torques on B about joint 1's and joint 2's axes; A's orientation is a unit quaternion
``(w, x, y, z)``, scalar first; twist is signed, right-handed about A's initial ``+z``.
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional

import numpy as np


@dataclass(frozen=True)
class Series:
    """A schedule sampled as the CLI's schedule file samples it: equal steps per phase (or a
    uniform rate), every phase boundary written twice (``boundary`` ``"end"`` then ``"start"``,
    with each side's one-sided values)."""

    #: Time from the start of the schedule, s, shape ``(n,)``.
    t: np.ndarray
    #: Joint angles ``(q1, q2)``, rad, shape ``(n, 2)``.
    q: np.ndarray
    #: Joint rates, rad/s, shape ``(n, 2)``.
    qd: np.ndarray
    #: Joint accelerations, rad/s², shape ``(n, 2)``.
    qdd: np.ndarray
    #: Motor torques on B about joint 1's and joint 2's axes (exact inverse dynamics), N·m, ``(n, 2)``.
    tau: np.ndarray
    #: Impulse of a rate jump on the ``start`` row where it lands, N·m·s, ``(n, 2)`` (else 0).
    impulse: np.ndarray
    #: A's orientation, unit quaternion ``(w, x, y, z)``, shape ``(n, 4)``.
    orientation: np.ndarray
    #: Twist of A about its initial ``+z``, continued, degrees, ``(n,)``.
    twist_deg: np.ndarray
    #: Swing of A's spine axis, degrees, ``(n,)``.
    swing_deg: np.ndarray
    #: The piece (phase) of each row.
    phase: List[str]
    #: ``""``, or ``"end"`` / ``"start"`` on the two rows of a piece boundary.
    boundary: List[str]
    #: The CSV text itself (the file ``catflip run`` writes).
    csv: str = field(repr=False)
    #: Its sidecar ``NAME.json`` (units, conventions, model, jumps), when catflip made the series.
    sidecar: Optional[str] = field(default=None, repr=False)

    @staticmethod
    def from_csv(text: str, sidecar: Optional[str] = None) -> "Series":
        """Reads a schedule file written by catflip (``NAME.csv``, and its sidecar's text)."""
        rows = list(csv.DictReader(io.StringIO(text)))

        def col(name: str) -> np.ndarray:
            return np.array([float(r[name]) for r in rows], dtype=float)

        def pair(a: str, b: str) -> np.ndarray:
            return np.column_stack([col(a), col(b)]) if rows else np.zeros((0, 2))

        return Series(
            t=col("t_s"),
            q=pair("q1_rad", "q2_rad"),
            qd=pair("qd1_rad_s", "qd2_rad_s"),
            qdd=pair("qdd1_rad_s2", "qdd2_rad_s2"),
            tau=pair("tau1_nm", "tau2_nm"),
            impulse=pair("impulse1_nms", "impulse2_nms"),
            orientation=np.column_stack([col(c) for c in ("qw", "qx", "qy", "qz")]) if rows else np.zeros((0, 4)),
            twist_deg=col("twist_deg"),
            swing_deg=col("swing_deg"),
            phase=[r["phase"] for r in rows],
            boundary=[r["boundary"] for r in rows],
            csv=text,
            sidecar=sidecar,
        )

    def __repr__(self) -> str:
        # Its rows are summarised: the arrays (and the per-row phase names) can run to thousands.
        phases = list(dict.fromkeys(self.phase))
        span = f"t {self.t[0]:g}–{self.t[-1]:g} s" if len(self.t) else "empty"
        return f"Series({len(self.t)} rows, {span}, phases {phases})"

    def to_dict(self) -> Dict[str, Any]:
        """Every column by name (``q1``, ``q2``, ``tau1`` … split per joint, the jump impulses,
        each row's ``phase`` and ``boundary``), for a data frame: the schedule file's columns."""
        return {
            "t": self.t,
            "q1": self.q[:, 0],
            "q2": self.q[:, 1],
            "qd1": self.qd[:, 0],
            "qd2": self.qd[:, 1],
            "qdd1": self.qdd[:, 0],
            "qdd2": self.qdd[:, 1],
            "tau1": self.tau[:, 0],
            "tau2": self.tau[:, 1],
            "impulse1": self.impulse[:, 0],
            "impulse2": self.impulse[:, 1],
            "qw": self.orientation[:, 0],
            "qx": self.orientation[:, 1],
            "qy": self.orientation[:, 2],
            "qz": self.orientation[:, 3],
            "twist_deg": self.twist_deg,
            "swing_deg": self.swing_deg,
            "phase": list(self.phase),
            "boundary": list(self.boundary),
        }


@dataclass(frozen=True)
class Measurement:
    """One schedule through one engine: the report of ``catflip simulate --json`` (``report``,
    the same numbers), its headline figures, and the schedule's time series."""

    #: The CLI's JSON report, as a dict.
    report: Dict[str, Any]
    #: The schedule sampled (the exact engine's torques and orientation); ``None`` when not asked
    #: for, or for a schedule imported from elsewhere (its own arrays are what was given).
    series: Optional[Series] = None

    @property
    def engine(self) -> str:
        """``"exact"`` or ``"rapier"``."""
        return self.report["engine"]

    @property
    def twist_deg(self) -> float:
        """Signed twist of A about its initial ``+z``, degrees (180 is the flip)."""
        return self.report["twist_deg"]

    @property
    def swing_deg(self) -> float:
        """Swing of A's spine axis, degrees (0 is the flip)."""
        return self.report["swing_deg"]

    @property
    def peak_torque_nm(self) -> float:
        """The largest motor torque over the schedule, N·m."""
        return self.report["peak_torque_nm"]["max"]

    @property
    def verdict(self) -> Optional[str]:
        """rapier's verdict against the exact engine (``verified``, ``not verified …``,
        ``inconclusive``); ``None`` for the exact engine."""
        return self.report.get("verdict")


@dataclass(frozen=True)
class Optimization:
    """``catflip optimize --json``: the profile QP, its exact refinement and the retiming of every
    phase (``report``), and each optimum's time series by its name in the results."""

    report: Dict[str, Any]
    series: Dict[str, Series] = field(default_factory=dict)


@dataclass(frozen=True)
class WholeOptimum:
    """``catflip optimize --whole --json``: the whole-manoeuvre optimum (``report``) and its time
    series (``None`` when no start flipped the cat: ``report["status"]`` says why)."""

    report: Dict[str, Any]
    series: Optional[Series] = None

    @property
    def solved(self) -> bool:
        """Whether there is an optimum."""
        return self.report.get("twist_deg") is not None
