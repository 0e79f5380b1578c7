"""``--gui``: PyBullet's own window where a display exists. Without one, ``evaluate --gui`` and
``baseline --gui`` stop before any work with one line naming the flag (exit code 2, nothing
written, nothing swept); the window's wait ends when it is closed or at Ctrl-C."""

from __future__ import annotations

import os
import signal
import subprocess
import sys

import pytest

from ergohandover import sim
from ergohandover.cli import build_parser, main
from ergohandover.errors import ConfigError
from ergohandover.executor import Stopped
from ergohandover.scene.world import World

COMMANDS = {"evaluate": ["--points", "POINTS"], "baseline": ["--start", "0,1.1,0.6"]}


@pytest.fixture
def no_display(monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)


def everything_under(*folders) -> list:
    return sorted(p for folder in folders for p in folder.rglob("*"))


@pytest.mark.parametrize("command", list(COMMANDS))
@pytest.mark.parametrize("output", [True, False])
def test_gui_without_a_display_stops_before_any_work(no_display, tmp_path, monkeypatch, capsys,
                                                     landscape_cache, command, output):
    points = tmp_path / "points.csv"
    points.write_text("x,y,z\n0,1.1,0.4\n")
    argv = [command, *(str(points) if a == "POINTS" else a for a in COMMANDS[command]), "--gui"]
    if output:
        argv += ["--output", str(tmp_path / "out" / "result.csv")]
    monkeypatch.chdir(tmp_path)  # the default output, runs/<command>/..., would land here
    before = everything_under(tmp_path, landscape_cache)
    capsys.readouterr()
    assert main(argv) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.count("\n") == 1 and "Traceback" not in captured.err
    assert captured.err.startswith(f"ergohandover {command}: error: --gui needs a display: "
                                   "neither DISPLAY nor WAYLAND_DISPLAY is set")
    assert "ergohandover view" in captured.err
    assert everything_under(tmp_path, landscape_cache) == before, "--gui left a file behind"


@pytest.mark.slow
def test_the_installed_command_says_it_in_one_line(tmp_path):
    points = tmp_path / "points.csv"
    points.write_text("x,y,z\n0,1.1,0.4\n")
    env = {k: v for k, v in os.environ.items() if k not in sim.DISPLAY_VARIABLES}
    result = subprocess.run([sys.executable, "-m", "ergohandover.cli", "evaluate", "--points",
                             str(points), "--gui"], capture_output=True, text=True, env=env,
                            cwd=tmp_path, timeout=300)
    assert result.returncode == 2 and result.stdout == ""
    assert result.stderr.splitlines() == [
        "ergohandover evaluate: error: --gui needs a display: neither DISPLAY nor "
        "WAYLAND_DISPLAY is set; use `ergohandover view` for a browser view"]
    assert list(tmp_path.iterdir()) == [points]


def test_connecting_a_window_without_a_display_raises_one_line(no_display):
    with pytest.raises(ConfigError) as caught:
        sim.connect_gui()
    assert str(caught.value) == ("--gui needs a display: neither DISPLAY nor WAYLAND_DISPLAY is "
                                 "set; use `ergohandover view` for a browser view")
    with pytest.raises(sim.NoDisplayError, match=r"^render_mode = 'human' needs a display"):
        sim.require_display("render_mode = 'human'")
    with pytest.raises(sim.NoDisplayError, match=r"^--gui needs a display"):
        World(gui=True)


@pytest.mark.parametrize("variable", sim.DISPLAY_VARIABLES)
def test_either_display_variable_is_a_display(no_display, monkeypatch, variable):
    assert not sim.has_display()
    monkeypatch.setenv(variable, ":99")
    assert sim.has_display()
    sim.require_display()  # no error


@pytest.mark.parametrize("command", list(COMMANDS))
def test_the_flag_says_what_it_does(command):
    parser = build_parser().commands[command]
    flag = parser._option_string_actions["--gui"]
    assert flag.default is False
    assert "PyBullet's own window" in flag.help and "needs a display" in flag.help
    assert "ergohandover view" in flag.help
    assert ("first point" if command == "evaluate" else "optimised location") in flag.help


def test_the_wait_ends_when_the_window_is_gone_or_at_ctrl_c(monkeypatch):
    client = sim.connect_direct()
    try:
        def ctrl_c(_seconds):
            raise KeyboardInterrupt

        monkeypatch.setattr(sim.time, "sleep", ctrl_c)
        sim.wait_while_open(client)  # Ctrl-C ends the looking, not the command

        def killed(_seconds):
            raise Stopped

        monkeypatch.setattr(sim.time, "sleep", killed)
        with pytest.raises(Stopped) as caught:  # kill still stops the command
            sim.wait_while_open(client)
        assert caught.value.signal_number == signal.SIGTERM
    finally:
        sim.pybullet().disconnect(client)
    sim.wait_while_open(client)  # closed: returns at once
