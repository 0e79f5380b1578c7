"""Body size of the simulated worker: stature, mass, landmarks, segment masses and joint limits.

A body is stature, mass and sex, plus whatever else of the person is measured; everything not
measured is filled in by the body model fitted to the ANSUR II survey (:mod:`.body_model`), and
:mod:`.proportions` turns the landmarks into segments. Sources are listed in
``docs/anthropometry.md``; the short form is:

* landmarks and percentiles: ANSUR II (Gordon et al. 2014, NATICK/TR-15/007), US Army 2012;
  the earlier fixed ratios (Drillis & Contini 1966 via Winter 2009) remain as an option;
* segment masses and centres of mass: Dempster via Winter (2009) Table 4.1;
* joint ranges of motion: AAOS (1965) norms, with Kapandji for the spine's own share.

All lengths are measured with the worker standing in the anatomical posture.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping
from dataclasses import dataclass
from functools import lru_cache
from statistics import NormalDist

import numpy as np

from ..errors import ConfigError
from .body_model import body_model, known_names, survey_rounding
from .joint_limits import default_joint_limits_deg, restriction_problem
from .proportions import (
    PROPORTIONS,
    disorder,
    in_order,
    ratio_landmarks,
    segment_sizes,
    survey_landmarks,
)

STATURE_RANGE_M = (1.40, 2.10)
MASS_RANGE_KG = (35.0, 160.0)
SEXES = ("male", "female")


class BodySpecError(ConfigError):
    """A body specification is outside what the model supports; the message is one line."""


ANSUR2 = {
    "male": (1.756, 0.0686, 85.5, 14.2),
    "female": (1.629, 0.0640, 67.8, 11.4),
}
"""ANSUR II (2012) summary statistics per sex: stature mean and SD [m], weight mean and SD [kg]
(the named percentiles and the population study's workforce are drawn from it)."""
_PERCENTILE_Z = {"p5": NormalDist().inv_cdf(0.05), "p50": 0.0, "p95": NormalDist().inv_cdf(0.95)}


def _percentile_table() -> dict[str, tuple[float, float, str]]:
    """Stature and mass for each named percentile, derived from the ANSUR II mean and SD.

    Stature is close to normal, so its percentile is mean + z SD. Body weight is right-skewed,
    so a normal fit would put the median above the real one; a log-normal with the same mean and
    SD is used instead. Stature and mass share one percentile: a "p5 worker" is small in both,
    which is the usual design convention, not a multivariate percentile.
    """
    table = {}
    for sex in ("female", "male"):
        h_mean, h_sd, m_mean, m_sd = ANSUR2[sex]
        sigma = math.sqrt(math.log(1.0 + (m_sd / m_mean) ** 2))
        mu = math.log(m_mean) - 0.5 * sigma**2
        for name, z in _PERCENTILE_Z.items():
            # Rounded to 1 mm and 0.1 kg, the resolution the survey reports.
            stature = round(h_mean + z * h_sd, 3)
            mass = round(math.exp(mu + z * sigma), 1)
            table[f"{name}-{sex}"] = (stature, mass, sex)
    return table


PERCENTILES: dict[str, tuple[float, float, str]] = _percentile_table()
"""Named percentile -> (stature [m], mass [kg], sex)."""

@dataclass(frozen=True)
class Segments:
    """Segment lengths and shape sizes of one worker [m], standing anatomical posture.

    The vertical chain ``ankle_height + shank_length + thigh_length + pelvis_height +
    trunk_length + neck_length + head_height`` equals stature.
    """

    ankle_height: float  # floor to ankle joint centre
    shank_length: float  # ankle joint to knee joint
    thigh_length: float  # knee joint to hip joint
    pelvis_height: float  # hip joint centres to lumbar joint (L5/S1), vertical
    trunk_length: float  # lumbar joint to neck joint (C7/T1)
    shoulder_drop: float  # neck joint down to the line through the shoulder joints
    neck_length: float  # C7/T1 to the head-neck (atlanto-occipital) joint
    head_height: float  # head-neck joint to the vertex
    eye_height_above_head_joint: float
    eye_forward: float  # eyes in front of the head-neck joint
    hip_width: float  # between the hip joint centres
    shoulder_width: float  # between the shoulder joint centres
    clavicle_length: float  # mid-line (sternoclavicular region) to shoulder joint
    upper_arm_length: float  # shoulder to elbow joint
    forearm_length: float  # elbow to wrist joint
    hand_length: float  # wrist to fingertip
    grip_offset: float  # wrist to the centre of a power grip, along the hand
    foot_length: float
    foot_width: float
    heel_to_ankle: float  # back of the heel to the ankle joint, horizontal
    trunk_depth: float
    trunk_width: float
    pelvis_width: float
    head_radius: float
    upper_arm_radius: float
    forearm_radius: float
    thigh_radius: float
    shank_radius: float

    @property
    def knee_height(self) -> float:
        """Floor to knee joint, standing [m]."""
        return self.ankle_height + self.shank_length

    @property
    def hip_height(self) -> float:
        """Floor to hip joint centres, standing [m]."""
        return self.knee_height + self.thigh_length

    @property
    def neck_joint_height(self) -> float:
        """Floor to the neck joint (C7/T1), standing [m]."""
        return self.hip_height + self.pelvis_height + self.trunk_length

    @property
    def shoulder_height(self) -> float:
        """Floor to the shoulder joint centres, standing [m]."""
        return self.neck_joint_height - self.shoulder_drop


@dataclass(frozen=True)
class SegmentMass:
    """Mass of one body segment and where its centre of mass lies.

    Attributes:
        mass_kg: Segment mass [kg].
        com_fraction: Centre of mass along the segment from its proximal joint [fraction of the
            segment's reference length]; the reference line of each segment is tabulated in
            ``docs/anthropometry.md``.
    """

    mass_kg: float
    com_fraction: float


# Winter (2009) Table 4.1 (Dempster): fraction of body mass, COM from the proximal joint.
# Proximal means nearer the pelvis, the model's root. Where our segment differs from Dempster's
# the COM is re-expressed on ours: trunk = thorax + abdomen (COM 0.63 from C7/T1, so 0.37 from
# the lumbar joint); pelvis measured up from the hip joints (Winter 0.105 down from L4/L5);
# head_neck COM at the ear canal, on the line C7/T1 to vertex; hand COM 0.506 of wrist to the
# middle finger's second knuckle, which is ~0.79 of hand length, so ~0.40 of hand length.
_MASS = {
    "foot": (0.0145, 0.50),  # along ankle -> head of metatarsal II (Winter's line)
    "shank": (0.0465, 0.433),
    "thigh": (0.100, 0.433),
    "pelvis": (0.142, 1.0 - 0.105),
    "trunk": (0.355, 1.0 - 0.63),
    "head_neck": (0.081, (0.926 - 0.855) / (1.0 - 0.855)),  # ear canal 0.926, C7/T1 0.855
    "upper_arm": (0.028, 0.436),
    "forearm": (0.016, 0.430),
    "hand": (0.006, 0.40),
}
PAIRED_SEGMENTS = frozenset({"foot", "shank", "thigh", "upper_arm", "forearm", "hand"})

# Extensor strength of the joints that hold a load in front of the body, for the solver's effort
# task. Hip and knee: peak isometric moment as a fraction of body weight x stature, young adults
# (Anderson, Madigan & Nussbaum 2007, J Biomech 40:3105-3113, Table 3; read as coded in rbdl's
# Millard2016TorqueMuscle). Lower back: static torso extension of men at 20 deg of trunk flexion,
# 288 N m (Chaffin, Andersson & Martin 1999, Occupational Biomechanics, Table 4.5; read as
# quoted in J Electromyogr Kinesiol 2012;22:814, Table 2); the source gives one value, so it is
# scaled here by body weight x stature relative to the ANSUR II 50th-percentile man (an
# assumption, not a published ratio).
_STRENGTH_FRACTION = {"male": {"hip_flexion": 0.161, "knee_flexion": 0.163},
                      "female": {"hip_flexion": 0.181, "knee_flexion": 0.159}}
LUMBAR_STRENGTH_NM = 288.0
# The hamstrings' passive length, as a line in (knee flexion, hip flexion) on which hip flexion
# stops [deg]: 61 +/- 6.7 with the knee straight (passive straight-leg raise, pelvis strapped)
# and, at 90 of hip flexion, the knee straightens to 31 +/- 7.5 of flexion and no further
# (passive knee extension test): Gajdosik et al. 1993, J Orthop Sports Phys Ther 18:614-618,
# 30 men. Straight between the two points (constant moment arms, an assumption), up to the
# hip's own limit. Women are ~8 deg more flexible (Youdas et al. 2005, J Orthop Sports Phys Ther
# 35:246); one line serves both sexes, the men's.
HAMSTRING_HIP_AT_STRAIGHT_KNEE_DEG = 61.0
HAMSTRING_KNEE_AT_HIP_90_DEG = 31.0
GRAVITY = 9.81  # [m/s²], the one value of the twin (body weights, the effort task)


def _check_range(field: str, value: object, valid: tuple[float, float], unit: str) -> None:
    """Raise BodySpecError unless ``value`` is a finite real number within ``valid``."""
    lo, hi = valid
    decimals = 2 if unit == "m" else 0
    span = f"{lo:.{decimals}f}-{hi:.{decimals}f} {unit}"
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise BodySpecError(f"{field} = {value!r} is not a number; the valid range is {span}")
    number = float(value)
    if not math.isfinite(number):
        raise BodySpecError(f"{field} = {number!r} is not finite; the valid range is {span}")
    if not lo <= number <= hi:
        raise BodySpecError(f"{field} = {number!r} is outside the valid range {span}")


@dataclass(frozen=True)
class BodySpec:
    """Size of one worker; the default is the ANSUR II 50th-percentile man.

    Attributes:
        stature_m: Standing height [m], 1.40-2.10.
        mass_kg: Body mass [kg], 35-160.
        sex: "male" or "female": the survey's model of that sex fills in what is not measured.
        measurements: The person's own measurements beyond stature and mass, as sorted
            ``(name, value)`` pairs in metres (names: :func:`~.body_model.known_names`); any
            landmark not given is the body model's mean given the ones that are.
        proportions: "ansur2" (landmarks from the survey's body model) or "drillis-contini"
            (the fixed-ratio twin: every length a fixed fraction of stature; no measurements).
        restrictions: joints whose range is narrower than the default (an impaired worker:
            a shoulder that cannot flex past 90°, an elbow that lacks 30° of extension), as
            sorted ``(joint, lower, upper)`` [deg], each joint as :meth:`joint_limits_deg`
            names it and each range within its default.
    """

    stature_m: float = PERCENTILES["p50-male"][0]
    mass_kg: float = PERCENTILES["p50-male"][1]
    sex: str = "male"
    measurements: tuple[tuple[str, float], ...] = ()
    proportions: str = "ansur2"
    restrictions: tuple[tuple[str, float, float], ...] = ()

    def __post_init__(self) -> None:
        """Validate the fields so that an impossible body fails here, not deep in a simulation."""
        _check_range("stature_m", self.stature_m, STATURE_RANGE_M, "m")
        _check_range("mass_kg", self.mass_kg, MASS_RANGE_KG, "kg")
        if self.sex not in SEXES:
            raise BodySpecError(
                f"sex = {self.sex!r} is not valid; the valid values are {', '.join(SEXES)}"
            )
        if self.proportions not in PROPORTIONS:
            raise BodySpecError(f"proportions = {self.proportions!r} is not valid; the valid "
                                f"values are {', '.join(PROPORTIONS)}")
        if self.measurements and self.proportions != "ansur2":
            raise BodySpecError(f"proportions = {self.proportions!r} takes no measurements "
                                "(its lengths are fractions of stature); use ansur2")
        check_measurements(dict(self.measurements), self.sex)
        problem = restriction_problem(self.restrictions)
        if problem:
            raise BodySpecError(problem)
        marks = landmarks_of(self)
        for name, value in self.measurements:
            if abs(marks[name] - value) > 0.001:  # redundant measurements that disagree
                raise BodySpecError(f"{name} = {value!r} disagrees with the other measurements "
                                    f"(they make it {marks[name]:.3f} m)")
        order = disorder(marks)
        if order:
            lower, upper = order
            raise BodySpecError(f"{lower} = {marks[lower]:.3f} m is not below {upper} = "
                                f"{marks[upper]:.3f} m: the measurements do not fit one body")

    @classmethod
    def from_percentile(cls, name: str) -> BodySpec:
        """Worker of a named ANSUR II percentile, e.g. ``"p5-female"`` or ``"p95-male"``.

        Args:
            name: One of the keys of ``PERCENTILES``.

        Returns:
            The body with that percentile's stature [m], mass [kg] and sex; its other
            landmarks are the body model's means given those.

        Raises:
            BodySpecError: If the name is unknown; the message lists the valid names.
        """
        if name not in PERCENTILES:
            raise BodySpecError(
                f"unknown percentile {name!r}; the valid names are {', '.join(PERCENTILES)}"
            )
        stature, mass, sex = PERCENTILES[name]
        return cls(stature_m=stature, mass_kg=mass, sex=sex)

    @classmethod
    def from_measurements(cls, measurements: Mapping[str, float], sex: str = "male") -> BodySpec:
        """A person's body from whatever of their measurements are known [m, kg].

        Stature and mass, if missing, are the body model's means given the rest (rounded to
        the survey's 1 mm and 0.1 kg); so is every landmark not given.

        Raises:
            BodySpecError: an unknown name, a value that is not a plausible length, or values
                that do not fit one body (an elbow above the shoulder); one line.
        """
        if sex not in SEXES:
            raise BodySpecError(f"sex = {sex!r} is not valid; the valid values are "
                                f"{', '.join(SEXES)}")
        given = dict(measurements)
        check_measurements(given, sex, fields=True)
        if "stature_m" not in given or "mass_kg" not in given:
            model = body_model()[sex]
            filled = dict(zip(model.names, model.conditional(given), strict=True))
            given.setdefault("stature_m", round(float(filled["stature_m"]), 3))
            given.setdefault("mass_kg", round(float(filled["mass_kg"]), 1))
        stature, mass = float(given.pop("stature_m")), float(given.pop("mass_kg"))
        return cls(stature, mass, sex, tuple(sorted((k, float(v)) for k, v in given.items())))

    @classmethod
    def sample(cls, n: int, sex: str, rng: np.random.Generator) -> list[BodySpec]:
        """``n`` people of one sex drawn from the survey's body model, every measurement
        their own (rounded to 1 mm and 0.1 kg). A draw outside the model's valid range
        (stature, mass) or whose landmarks are out of anatomical order is drawn again."""
        model = body_model()[sex]
        rows = np.empty((0, len(model.names)))
        while len(rows) < n:
            draws = model.sample(n - len(rows), rng)
            draws = survey_rounding(draws, model.names)
            columns = dict(zip(model.names, draws.T, strict=True))
            keep = in_order(survey_landmarks(columns))
            for name, valid in (("stature_m", STATURE_RANGE_M), ("mass_kg", MASS_RANGE_KG)):
                keep &= (columns[name] >= valid[0]) & (columns[name] <= valid[1])
            rows = np.vstack([rows, draws[keep]])
        return [cls.from_measurements(dict(zip(model.names, map(float, row), strict=True)), sex)
                for row in rows]

    def landmarks(self) -> dict[str, float]:
        """Every landmark height and length of this body [m] (mass [kg]): the measurements,
        the derived quantities (``elbow_height_m``, ``arm_length_m``, ...) and the joints."""
        return dict(landmarks_of(self))

    @property
    def elbow_height_m(self) -> float:
        """Standing elbow height [m]: floor to the underside of the elbow, as ergonomics uses
        it (the fixed-ratio twin: its elbow joint)."""
        return landmarks_of(self)["elbow_height_m"]

    @property
    def elbow_joint_height_m(self) -> float:
        """Floor to the elbow joint, arm hanging [m]."""
        return landmarks_of(self)["elbow_joint_height_m"]

    @property
    def shoulder_height_m(self) -> float:
        """Floor to the shoulder joint (the acromion) [m]."""
        return landmarks_of(self)["shoulder_height_m"]

    @property
    def arm_length_m(self) -> float:
        """Shoulder joint to wrist, arm hanging [m]."""
        return landmarks_of(self)["arm_length_m"]

    def segments(self) -> Segments:
        """Segment lengths and shape sizes [m] from this body's landmarks."""
        sizes = segment_sizes(landmarks_of(self))
        return Segments(**{name: float(value) for name, value in sizes.items()})

    def segment_masses(self) -> dict[str, SegmentMass]:
        """Mass [kg] and COM fraction of each segment; paired ones are per side.

        The Winter fractions sum to 1.000 already; they are divided by their sum anyway so the
        segments (paired ones counted twice) add up to ``mass_kg`` to rounding error.
        """
        total = sum(f * (2 if n in PAIRED_SEGMENTS else 1) for n, (f, _) in _MASS.items())
        return {n: SegmentMass(self.mass_kg * f / total, c) for n, (f, c) in _MASS.items()}

    def joint_strengths_nm(self) -> dict[str, float]:
        """Extensor strength [N m] of the knee, hip and lower back (``lumbar_flexion``)."""
        weight_height = self.mass_kg * GRAVITY * self.stature_m
        stature, mass, _ = PERCENTILES["p50-male"]
        reference = mass * GRAVITY * stature
        out = {j: f * weight_height for j, f in _STRENGTH_FRACTION[self.sex].items()}
        out["lumbar_flexion"] = LUMBAR_STRENGTH_NM * weight_height / reference
        return out

    @staticmethod
    def hamstring_line() -> tuple[float, float]:
        """Hip flexion where the hamstrings stop it with the knee straight [rad], and how much
        more each radian of knee flexion allows [1]."""
        hip0 = HAMSTRING_HIP_AT_STRAIGHT_KNEE_DEG
        return math.radians(hip0), (90.0 - hip0) / HAMSTRING_KNEE_AT_HIP_90_DEG

    def joint_limits_deg(self) -> dict[str, tuple[float, float]]:
        """Lower and upper joint limits [deg], positive in the named direction.

        Arm joints appear twice, with ``left_`` and ``right_`` prefixes and identical values:
        the signed conventions mirror between sides, so the numbers do not.
        """
        limits = default_joint_limits_deg()
        limits.update({name: (lo, hi) for name, lo, hi in self.restrictions})
        return limits


PLAUSIBLE_SDS = 6.0
"""A measurement further than this many SDs from its sex's survey mean is refused."""


def check_measurements(given: dict, sex: str, fields: bool = False) -> None:
    """Raise BodySpecError on an unknown name or an implausible value (one line).

    Stature and mass are fields of BodySpec, so they are measurements only when ``fields``.
    """
    model = body_model()[sex]
    for name, value in given.items():
        if fields and name == "stature_m":
            _check_range(name, value, STATURE_RANGE_M, "m")
            continue
        if fields and name == "mass_kg":
            _check_range(name, value, MASS_RANGE_KG, "kg")
            continue
        if name not in known_names() or name in ("stature_m", "mass_kg"):
            allowed = [n for n in known_names() if fields or n not in ("stature_m", "mass_kg")]
            raise BodySpecError(f"{name} is not a known measurement; the known ones are "
                                f"{', '.join(allowed)}")
        lo, hi = model.value_range(name, PLAUSIBLE_SDS)
        _check_range(name, value, (max(lo, 0.0), hi), "m")


@lru_cache(maxsize=4096)
def landmarks_of(body: BodySpec) -> dict[str, float]:
    """The landmarks of ``body`` (cached: bodies are immutable); callers must not mutate."""
    if body.proportions == "drillis-contini":
        return ratio_landmarks(body.stature_m)
    given = {"stature_m": body.stature_m, "mass_kg": body.mass_kg, **dict(body.measurements)}
    model = body_model()[body.sex]
    values = dict(zip(model.names, map(float, model.conditional(given)), strict=True))
    return {name: float(v) for name, v in survey_landmarks(values).items()}
