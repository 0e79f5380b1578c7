"""constraints.txt, the lock a reviewer installs from, pins exactly the third-party versions
every committed results/*/manifest.json records. The manifests must agree with each other: one
lock reproduces one environment, so a part rerun under other versions shows here until every
part is rerun under them (and the lock follows) or the part is rerun under the locked ones."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from packaging.requirements import Requirement
from packaging.utils import canonicalize_name
from packaging.version import Version

ROOT = Path(__file__).resolve().parents[1]
LOCK = ROOT / "constraints.txt"
NOT_PINNED = ("python", "ergohandover")  # pip cannot pin the interpreter; the package is ours


def manifests() -> dict[str, dict[str, str]]:
    """Each committed part's manifest's versions, by the part's folder."""
    found = {p.parent.name: json.loads(p.read_text())["versions"]
             for p in sorted((ROOT / "results").glob("*/manifest.json"))
             if p.parent.name != "quick"}  # quick/ is a smoke run of its own
    assert found, "no results/*/manifest.json"
    return found


def locked() -> dict[str, str]:
    """constraints.txt's pins: canonical name -> exact version."""
    pins = {}
    for number, line in enumerate(LOCK.read_text().splitlines(), 1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        req = Requirement(line)
        (spec,) = req.specifier  # one exact pin a line, nothing else
        assert spec.operator == "==" and not req.extras and req.marker is None, (
            f"constraints.txt line {number}: {line!r} is not NAME==VERSION")
        name = canonicalize_name(req.name)
        assert name not in pins, f"constraints.txt pins {req.name} twice"
        pins[name] = spec.version
    return pins


def shared() -> dict[str, str]:
    """The versions every manifest records, once the manifests are known to agree."""
    return next(iter(manifests().values()))


def test_the_committed_manifests_record_one_environment():
    by_versions: dict[str, list[str]] = {}
    for part, versions in manifests().items():
        by_versions.setdefault(json.dumps(versions, sort_keys=True), []).append(part)
    assert len(by_versions) == 1, "the manifests record different versions: " + "; ".join(
        f"{', '.join(parts)}: {versions}" for versions, parts in by_versions.items())


def test_the_lock_pins_exactly_the_manifests_third_party_versions():
    recorded = {canonicalize_name(name): version for name, version in shared().items()
                if name not in NOT_PINNED}
    assert locked() == recorded


def test_the_lock_names_the_manifests_python():
    stated = re.findall(r"python (\d+\.\d+\.\d+)", LOCK.read_text())
    assert stated == [shared()["python"]]


def test_each_pin_is_within_the_packages_declared_range():
    # a pin outside pyproject.toml's range would make `pip install -e . -c constraints.txt` fail
    tomllib = pytest.importorskip("tomllib")  # Python 3.11 on
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    declared = {canonicalize_name(r.name): r for r in map(
        Requirement, project["dependencies"])}  # the rest arrive as others' dependencies
    outside = {name: f"{version} not in {declared[name].specifier}"
               for name, version in locked().items()
               if name in declared and not declared[name].specifier.contains(Version(version))}
    assert not outside
