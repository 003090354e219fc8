"""Security of ``pare view``: loopback only, read-only, nothing outside the run folders."""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import pytest
from starlette.testclient import TestClient

from pare.cli import main
from pare.errors import UserInputError
from pare.viewer import Catalog, OutsideRunError, Site, confined
from pare.viewer._server import bind, check_loopback, create_app, url_of
from tests.viewer.runs import Runs

SECRET = "TOP-SECRET-7d41"


@pytest.fixture
def copy(runs: Runs, tmp_path: Path) -> Path:
    """A copy of the model-backed run that a test may damage, beside a secret file outside it."""
    (tmp_path / "secret.json").write_text(json.dumps({"steps": [], "secret": SECRET}), encoding="utf-8")
    folder = tmp_path / "runs" / "models"
    shutil.copytree(runs.models, folder)
    return folder


def client(*folders: Path) -> TestClient:
    return TestClient(create_app(Site(Catalog.open(folders))), base_url="http://127.0.0.1")


@pytest.mark.parametrize("host", ["127.0.0.1", "localhost", "::1", "127.0.0.2"])
def test_loopback_hosts_are_accepted(host: str) -> None:
    check_loopback(host)


@pytest.mark.parametrize("host", ["0.0.0.0", "::", "192.168.1.10", "10.0.0.1", "example.com", ""])
def test_other_hosts_are_refused(host: str) -> None:
    with pytest.raises(UserInputError, match="loopback interface only"):
        check_loopback(host)


def test_the_command_refuses_to_listen_beyond_loopback(
    runs: Runs, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["view", str(runs.oracle), "--host", "0.0.0.0"]) == 2
    assert "loopback interface only" in capsys.readouterr().err


def test_a_free_loopback_port_is_bound_by_default() -> None:
    sock = bind("127.0.0.1", 0)
    try:
        host, port = sock.getsockname()
        assert host == "127.0.0.1" and port > 0
        assert url_of(sock) == f"http://127.0.0.1:{port}/"
    finally:
        sock.close()


@pytest.mark.parametrize("method", ["POST", "PUT", "PATCH", "DELETE"])
def test_only_reading_is_allowed(runs: Runs, method: str) -> None:
    response = client(runs.models).request(method, "/index.html")
    assert response.status_code == 405


def test_pages_are_served_with_a_strict_policy(runs: Runs) -> None:
    response = client(runs.models).get("/")
    assert response.status_code == 200
    assert "script-src 'self'" in response.headers["content-security-policy"]
    assert response.headers["x-content-type-options"] == "nosniff"


@pytest.mark.parametrize("host", ["127.0.0.1:8765", "localhost:8765", "[::1]:8765"])
def test_loopback_host_names_are_served(runs: Runs, host: str) -> None:
    assert client(runs.models).get("/", headers={"host": host}).status_code == 200


def test_a_foreign_host_name_is_refused(runs: Runs) -> None:
    response = client(runs.models).get("/", headers={"host": "attacker.example"})
    assert response.status_code == 400


@pytest.mark.parametrize(
    "path",
    [
        "/../../../../etc/passwd",
        "/%2e%2e/%2e%2e/%2e%2e/etc/passwd",
        "/..%2f..%2f..%2fetc%2fpasswd",
        "/static/../_site.py",
        "/static/..%2f_site.py",
        "/static/%2e%2e/_site.py",
        "//etc/passwd",
        "/etc/passwd",
        "/c/models/manifest.json",
        "/c/models/episodes.jsonl",
        "/c/models/trajectories/dentist_moves_checkup/run-1.json",
        "/c/models/e/..%2f..%2fsecret/run-1.html",
        "/c/models/e/%2Fetc%2Fpasswd/run-1.html",
        "/c/models/e/dentist_moves_checkup/../../../manifest.json",
        "/c/..%2f..%2f/index.html",
        "/c/models/e/dentist_moves_checkup/run-1.html%00.json",
    ],
)
def test_paths_outside_the_site_are_not_found(copy: Path, path: str) -> None:
    response = client(copy).get(path)
    assert response.status_code == 404
    assert SECRET not in response.text and "root:" not in response.text


def test_a_record_naming_a_file_outside_its_run_is_refused(copy: Path) -> None:
    lines = (copy / "episodes.jsonl").read_text(encoding="utf-8").splitlines()
    record = json.loads(lines[0])
    record["trajectory"] = "../../secret.json"
    lines[0] = json.dumps(record)
    (copy / "episodes.jsonl").write_text("\n".join(lines) + "\n", encoding="utf-8")
    response = client(copy).get(f"/c/models/e/{record['scenario_id']}/run-{record['run']}.html")
    assert response.status_code == 200
    assert SECRET not in response.text and "not a plain relative path" in response.text


def test_a_trajectory_symlinked_out_of_its_run_is_refused(copy: Path) -> None:
    record = json.loads((copy / "episodes.jsonl").read_text(encoding="utf-8").splitlines()[0])
    file = copy / record["trajectory"]
    file.unlink()
    os.symlink(copy.parent.parent / "secret.json", file)
    response = client(copy).get(f"/c/models/e/{record['scenario_id']}/run-{record['run']}.html")
    assert SECRET not in response.text and "leads outside" in response.text


@pytest.mark.parametrize("relative", ["../x", "/etc/passwd", "a/../../x", "a\\..\\x", "C:/x", "", "a\x00b"])
def test_confined_refuses_anything_but_a_plain_path_inside(tmp_path: Path, relative: str) -> None:
    with pytest.raises(OutsideRunError):
        confined(tmp_path, relative)


def test_confined_allows_a_symlink_that_stays_inside(tmp_path: Path) -> None:
    (tmp_path / "real.json").write_text("{}", encoding="utf-8")
    (tmp_path / "link.json").symlink_to(tmp_path / "real.json")
    assert confined(tmp_path, "link.json") == (tmp_path / "real.json").resolve()
