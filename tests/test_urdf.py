"""The worker's URDF: written atomically, never stale, loads cleanly and agrees with numpy."""

from __future__ import annotations

import ctypes
import os
import sys
import tempfile
from pathlib import Path

import numpy as np
import pybullet as p
import pytest
from pybullet_utils.bullet_client import BulletClient

from ergohandover.io.atomic import OutputError
from ergohandover.twin.anthropometry import BodySpec
from ergohandover.twin.kinematics import KinematicModel
from ergohandover.twin.skeleton import build_skeleton
from ergohandover.twin.urdf import (
    cached_urdf,
    default_urdf_path,
    load_worker,
    urdf_text,
    write_urdf,
)

BODIES = {"p50-male": BodySpec(), "p5-female": BodySpec.from_percentile("p5-female")}
TOL = 1e-6  # [m] and [rad]; PyBullet reports link states in single precision (~1e-7)


@pytest.fixture
def client():
    """A DIRECT-mode PyBullet client, always disconnected afterwards."""
    cid = p.connect(p.DIRECT)
    try:
        yield cid
    finally:
        p.disconnect(cid)


def silent_load(cid: int, body: BodySpec, cache: Path):
    """``load_worker`` with the C-level stdout and stderr captured; returns (worker, text)."""
    libc = ctypes.CDLL(None)
    sys.stdout.flush()
    sys.stderr.flush()
    libc.fflush(None)
    saved = os.dup(1), os.dup(2)
    with tempfile.TemporaryFile() as sink:
        os.dup2(sink.fileno(), 1)
        os.dup2(sink.fileno(), 2)
        try:
            worker = load_worker(cid, body, cache)
        finally:
            libc.fflush(None)  # PyBullet prints through C stdio, which buffers
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            os.close(saved[0])
            os.close(saved[1])
        sink.seek(0)
        return worker, sink.read().decode(errors="replace")


def test_committed_default_urdf_is_current():
    assert default_urdf_path().read_text() == urdf_text(BodySpec())


def test_text_is_deterministic_and_per_body():
    assert urdf_text(BodySpec()) == urdf_text(None)
    assert urdf_text(BODIES["p5-female"]) != urdf_text(BodySpec())
    assert "-0 " not in urdf_text(BodySpec())  # no negative zeros to churn diffs


def test_write_urdf_is_atomic(tmp_path):
    target = tmp_path / "worker.urdf"
    target.write_text("old")
    assert write_urdf(BODIES["p5-female"], target) == target
    assert target.read_text() == urdf_text(BODIES["p5-female"])
    assert [f.name for f in tmp_path.iterdir()] == ["worker.urdf"]  # no temporary left
    with pytest.raises(OutputError):
        write_urdf(BodySpec(), tmp_path / "missing" / "worker.urdf")


def test_cached_urdf_is_reused_and_keyed_by_content(tmp_path):
    first = cached_urdf(BodySpec(), tmp_path)
    stamp = first.stat().st_mtime_ns
    assert cached_urdf(BodySpec(), tmp_path) == first
    assert first.stat().st_mtime_ns == stamp
    assert cached_urdf(BODIES["p5-female"], tmp_path) != first
    first.write_text("corrupt")
    assert cached_urdf(BodySpec(), tmp_path).read_text() == urdf_text(BodySpec())


@pytest.mark.parametrize("name", list(BODIES))
def test_loads_silently_with_every_joint_and_limit(client, tmp_path, name):
    body = BODIES[name]
    worker, printed = silent_load(client, body, tmp_path)
    assert printed == ""
    skeleton = build_skeleton(body)
    assert set(worker.joints) == {j.name for j in skeleton.joints}
    assert set(worker.links) == {link.name for link in skeleton.links}
    limits = body.joint_limits_deg()
    for joint in skeleton.joints:
        info = p.getJointInfo(worker.body_id, worker.joints[joint.name], physicsClientId=client)
        assert info[12].decode() == joint.child
        if joint.type == "fixed":
            assert info[2] == p.JOINT_FIXED
            continue
        assert info[2] == p.JOINT_REVOLUTE
        assert np.degrees([info[8], info[9]]) == pytest.approx(limits[joint.name], abs=1e-6)
        assert info[13] == pytest.approx(joint.axis)


def test_load_worker_accepts_a_bullet_client(tmp_path):
    bullet = BulletClient(connection_mode=p.DIRECT)
    try:
        worker = load_worker(bullet, BodySpec(), tmp_path)
        assert bullet.getNumJoints(worker.body_id) == len(worker.joints)
        assert worker.links["feet"] == -1
    finally:
        bullet.disconnect()


def _pose(cid: int, worker, model: KinematicModel, q: np.ndarray) -> None:
    for name in model.joint_names:
        p.resetJointState(worker.body_id, worker.joints[name], q[model.index(name)],
                          physicsClientId=cid)


def _angle(r_a: np.ndarray, r_b: np.ndarray) -> float:
    """Rotation angle between two rotation matrices [rad]."""
    return float(np.arccos(np.clip((np.trace(r_a.T @ r_b) - 1) / 2, -1.0, 1.0)))


@pytest.mark.parametrize("name", list(BODIES))
def test_numpy_link_frames_match_pybullet(client, tmp_path, name):
    body = BODIES[name]
    worker, _ = silent_load(client, body, tmp_path)
    model = KinematicModel(build_skeleton(body))
    q = np.random.default_rng(7).uniform(model.lower, model.upper, (64, model.nq))
    fk = model.forward(q)
    worst_pos = worst_rot = 0.0
    for n in range(len(q)):
        _pose(client, worker, model, q[n])
        for link, index in worker.links.items():
            if index < 0:
                continue
            state = p.getLinkState(worker.body_id, index, computeForwardKinematics=True,
                                   physicsClientId=client)
            quat = np.array(state[5]) / np.linalg.norm(state[5])
            rot = np.array(p.getMatrixFromQuaternion(quat)).reshape(3, 3)
            worst_pos = max(worst_pos, np.abs(np.array(state[4]) - fk.position(link)[n]).max())
            worst_rot = max(worst_rot, _angle(rot, fk.rotation(link)[n]))
    assert worst_pos < TOL
    assert worst_rot < TOL


@pytest.mark.parametrize("name", list(BODIES))
def test_numpy_com_matches_pybullet_mass_weighted_links(client, tmp_path, name):
    body = BODIES[name]
    worker, _ = silent_load(client, body, tmp_path)
    skeleton = build_skeleton(body)
    model = KinematicModel(skeleton)
    q = np.random.default_rng(8).uniform(model.lower, model.upper, (10, model.nq))
    for n in range(len(q)):
        _pose(client, worker, model, q[n])
        # PyBullet gives a fixed base zero mass, so the base's mass comes from the URDF.
        moment = skeleton.link("feet").mass * np.array(
            p.getBasePositionAndOrientation(worker.body_id, physicsClientId=client)[0])
        total = skeleton.link("feet").mass
        for link, index in worker.links.items():
            if index < 0:
                continue
            mass, _, inertia, local_com = p.getDynamicsInfo(
                worker.body_id, index, physicsClientId=client)[:4]
            assert mass == pytest.approx(skeleton.link(link).mass)
            assert inertia == pytest.approx(skeleton.link(link).inertia)
            assert local_com == pytest.approx(skeleton.link(link).com, abs=1e-9)
            state = p.getLinkState(worker.body_id, index, computeForwardKinematics=True,
                                   physicsClientId=client)
            moment += mass * np.array(state[0])
            total += mass
        assert model.com(q[n])[0] == pytest.approx(moment / total, abs=TOL)
