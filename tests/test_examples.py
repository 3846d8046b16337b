"""Every example command of the README and of ``run_mission --help`` works when pasted.

The fast tests read the examples (quoted where the shell would eat a character, scenarios listed,
a crash mid-mission); the slow test runs every one as written, in a shell, from the checkout,
on a private ROS domain, and checks its exit status.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import signal
import subprocess
import time
from pathlib import Path

import pytest
from fire_mission.runner import EXAMPLES, build_parser, shipped_scenarios

ROOT = Path(__file__).resolve().parents[1]
#: README commands not run here, and why
NOT_RUN = {"scripts/test": "the test suite itself"}
#: commands that serve until stopped: they must still be up after this many seconds, saying what for
SERVES = {"scripts/launch_agent": ("waits for the world node", 20.0)}


def readme_commands() -> list[str]:
    text = (ROOT / "README.md").read_text()
    out = []
    for block in re.findall(r"```bash\n(.*?)```", text, flags=re.S):
        for line in block.splitlines():
            cmd = re.sub(r"\s+#\s.*$", "", line).strip()
            if cmd and cmd not in NOT_RUN:
                out.append(cmd)
    return out


def help_commands() -> list[str]:
    return [c for c, _ in EXAMPLES]


def test_the_readme_has_examples_and_they_parse_as_shell() -> None:
    cmds = readme_commands()
    assert any(c.startswith("scripts/run_mission") for c in cmds)
    for c in cmds + help_commands():
        words = shlex.split(c)  # balanced quotes
        # nothing the shell would take for a redirection, a pipe or a glob outside quotes
        bare = re.sub(r"'[^']*'|\"[^\"]*\"", "", c)
        assert not re.search(r"[<>|;&*?]", bare), c
        assert words[0].startswith(("scripts/", "source")), c


def test_help_lists_the_scenarios_and_quoted_examples(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as e:
        build_parser().parse_args(["--help"])
    assert e.value.code == 0
    text = capsys.readouterr().out
    shipped = sorted(p.stem for p in (ROOT / "ros2_ws/src/fire_world_sim/scenarios").glob("*.yaml"))
    assert sorted(shipped_scenarios()) == shipped
    for name in shipped:
        assert re.search(rf"^  {name} ", text, flags=re.M), name
    for c in help_commands():
        assert c in text
    assert "--outage '0>1@3:9'" in text
    assert re.search(r"--kill 2@10\b", text)  # a crash mid-mission, not at the end


def test_a_bad_loss_is_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as e:
        build_parser().parse_args(["--loss", "2"])
    assert e.value.code == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line.startswith("run_mission: error: argument --loss: --loss expects a probability in [0, 1]")


def _run(cmd: str, env: dict[str, str], log: Path) -> tuple[int | None, str]:
    """Run ``cmd`` as pasted into bash at the checkout's root; (exit status or None: still up, output)."""
    serve = next((v for k, v in SERVES.items() if cmd.startswith(k)), None)
    with log.open("w") as f:
        proc = subprocess.Popen(
            ["bash", "-c", cmd], cwd=ROOT, env=env, stdout=f, stderr=subprocess.STDOUT, start_new_session=True
        )
        try:
            if serve is None:
                code: int | None = proc.wait(timeout=900)
            else:
                end = time.monotonic() + serve[1]
                while time.monotonic() < end and proc.poll() is None:
                    time.sleep(0.5)
                code = proc.poll()
        finally:
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGINT)
                try:
                    proc.wait(timeout=20)
                except subprocess.TimeoutExpired:
                    os.killpg(proc.pid, signal.SIGKILL)
                    proc.wait()
    return code, log.read_text()


@pytest.mark.slow
@pytest.mark.system
def test_every_example_runs_as_written(ros_env: dict[str, str], tmp_path: Path) -> None:
    runs = ROOT / "runs"
    before = set(runs.iterdir()) if runs.is_dir() else set()
    latest = os.readlink(runs / "latest") if (runs / "latest").is_symlink() else None
    cmds = list(dict.fromkeys(readme_commands() + help_commands()))
    failed = []
    try:
        for i, cmd in enumerate(cmds):
            code, out = _run(cmd, ros_env, tmp_path / f"example_{i}.log")
            serve = next((v for k, v in SERVES.items() if cmd.startswith(k)), None)
            if serve is not None:
                ok = code is None and serve[0] in out
            else:
                ok = code == 0 and "Traceback" not in out
            if not ok:
                failed.append(f"{cmd!r}: exit {code}: {out[-800:]}")
    finally:  # the runs and benchmarks the examples wrote
        for p in (set(runs.iterdir()) if runs.is_dir() else set()) - before:
            if p.is_dir() and not p.is_symlink():
                shutil.rmtree(p)
        if latest is not None:
            tmp = runs / ".latest-test"
            tmp.unlink(missing_ok=True)
            tmp.symlink_to(latest)
            os.replace(tmp, runs / "latest")
        elif (runs / "latest").is_symlink():
            (runs / "latest").unlink()
    assert not failed, "\n".join(failed)
