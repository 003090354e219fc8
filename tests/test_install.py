"""The install a user is told about installs this project, at the versions the suite was tested with."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import pytest
from packaging.requirements import Requirement
from packaging.utils import canonicalize_name

from pare import install

ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))


def _pins(lock: str) -> dict[str, str]:
    """Name -> version of every `name==version` line of a lock file."""
    pins: dict[str, str] = {}
    for line in (ROOT / "requirements" / lock).read_text(encoding="utf-8").splitlines():
        found = re.match(r"^([A-Za-z0-9._-]+)==([^\s;]+)", line)
        if found:
            pins[canonicalize_name(found.group(1))] = found.group(2)
    return pins


def _requirements(extras: tuple[str, ...]) -> list[Requirement]:
    """The project's requirements with the given extras, its own extras (``pare-bench[...]``) expanded."""
    project = PYPROJECT["project"]
    pending = [Requirement(text) for text in project["dependencies"]]
    pending += [Requirement(text) for extra in extras for text in project["optional-dependencies"][extra]]
    found: list[Requirement] = []
    while pending:
        requirement = pending.pop()
        if canonicalize_name(requirement.name) != canonicalize_name(install.DISTRIBUTION):
            found.append(requirement)
            continue
        for extra in requirement.extras:
            pending += [Requirement(text) for text in project["optional-dependencies"][extra]]
    return found


@pytest.mark.parametrize(("lock", "extras"), [("core.txt", ()), ("dev.txt", ("dev",))])
def test_each_lock_pins_every_requirement_within_its_range(lock: str, extras: tuple[str, ...]) -> None:
    pins = _pins(lock)
    for requirement in _requirements(extras):
        name = canonicalize_name(requirement.name)
        assert name in pins, f"requirements/{lock} does not pin {name}: run scripts/lock.sh"
        assert requirement.specifier.contains(pins[name], prereleases=True), (
            f"requirements/{lock} pins {name}=={pins[name]}, outside {requirement}: run scripts/lock.sh"
        )


def test_the_distribution_is_not_the_registry_s_other_pare() -> None:
    assert PYPROJECT["project"]["name"] == install.DISTRIBUTION != "pare"


def test_install_hints_name_this_project() -> None:
    # Installed from this checkout (editable): the hint installs the checkout itself.
    assert install.install_command("viewer") == f'pip install -e "{ROOT}[viewer]"'


def test_install_hints_outside_a_checkout_name_the_distribution(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(install, "_source_checkout", lambda: None)
    assert install.install_command("plots") == 'pip install "pare-bench[plots]"'


def test_no_document_tells_users_to_install_the_other_pare() -> None:
    texts = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md")), *sorted((ROOT / "src").rglob("*.py"))]
    wrong = re.compile(r"pip install\s+['\"]?pare(\[|['\"\s]|$)")
    offenders = [str(p.relative_to(ROOT)) for p in texts if wrong.search(p.read_text(encoding="utf-8"))]
    assert not offenders
