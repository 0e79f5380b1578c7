"""The participants' metadata and the summary statistics of the handover reference: a helper
of ``derive_handover_reference.py`` (see its docstring for the data set and the definitions).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

META_PAIR = re.compile(r"MetaData\s+Pair\s*(\d+)", re.IGNORECASE)
META_PERSON = re.compile(
    r"Participant\s*(\d+)\s*:\s*([A-Za-z]+)\s*,\s*Age\s*(\d+)\s*,\s*([A-Za-z-]+)\s*,"
    r"\s*Height\s*(\d+(?:\.\d+)?)\s*cm", re.IGNORECASE)


def read_metadata(root: Path) -> dict | None:
    files = sorted(p for p in root.rglob("*metadata*.txt") if p.is_file())
    if not files:
        return None
    entries, seen_pairs, unique = [], set(), []
    for path in files:
        text = path.read_text(encoding="utf-8", errors="replace")
        pair = META_PAIR.search(text)
        pair_no = int(pair.group(1)) if pair else None
        people = [
            {"file": path.relative_to(root).as_posix(), "pair": pair_no,
             "participant": int(m.group(1)), "sex": m.group(2).lower(), "age": int(m.group(3)),
             "handedness": m.group(4).lower(), "height_cm": float(m.group(5))}
            for m in META_PERSON.finditer(text)
        ]
        entries.extend(people)
        if pair_no not in seen_pairs:          # a pair split into parts is counted once
            seen_pairs.add(pair_no)
            unique.extend(people)
    heights = np.array([p["height_cm"] for p in unique], float)
    sexes = sorted({p["sex"] for p in unique})
    return {
        "participants": entries,
        "stature_cm": {**stats(heights, 1), "note": "one entry per participant; a pair listed "
                       "in several files is counted from the first file (sorted by path)"},
        "sex_counts": {s: sum(p["sex"] == s for p in unique) for s in sexes},
    }


# ---------------------------------------------------------------------------- output


def stats(values: np.ndarray, digits: int) -> dict:
    v = np.asarray(values, float)
    v = v[np.isfinite(v)]
    if len(v) == 0:
        return {"n": 0, "mean": None, "sd": None, "min": None, "max": None}
    return {
        "n": len(v),
        "mean": round(float(v.mean()), digits),
        "sd": round(float(v.std(ddof=1)), digits) if len(v) > 1 else None,
        "min": round(float(v.min()), digits),
        "max": round(float(v.max()), digits),
    }


def digits_for(key: str) -> int | None:
    if key.endswith("_deg"):
        return 1
    if key.endswith("_m"):
        return 3
    if key.endswith("_N"):
        return 1
    if key.endswith("_s"):
        return 3
    return None


def clean(obj, key: str = ""):
    """Plain JSON types; non-finite -> None; floats rounded by the unit suffix of their key."""
    if isinstance(obj, dict):
        return {str(k): clean(v, str(k)) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [clean(v, key) for v in obj]
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        value = float(obj)
        if not np.isfinite(value):
            return None
        d = digits_for(key)
        value = round(value, d) if d is not None else value
        return 0.0 if value == 0 else value
    return obj


def summarise(handovers: list[dict]) -> dict:
    def table(getter) -> dict:
        keys = sorted(getter(handovers[0]))
        return {k: stats(np.array([np.nan if getter(h)[k] is None else getter(h)[k]
                                   for h in handovers], float), digits_for(k) or 3)
                for k in keys}

    return {
        "n": len(handovers),
        "hand_counts": {side: sum(h["hand"] == side for h in handovers)
                        for side in ("left", "right")},
        "angles": {group: table(lambda h, g=group: h["angles"][g])
                   for group in ("receiving", "other", "trunk")},
        "object": table(lambda h: h["object"]),
        "body": table(lambda h: h["body"]),
    }
