"""The packages whose public names load on first use: each name in ``__all__`` resolves to the object
its module defines, nothing else resolves, and ``dir()`` lists them before they are loaded."""

from __future__ import annotations

import importlib
import subprocess
import sys

import pytest

LAZY_PACKAGES = ("frontier_rl", "frontier_rl.policies", "frontier_rl.swarm")


@pytest.mark.parametrize("package_name", LAZY_PACKAGES)
def test_every_public_name_resolves_to_its_modules_object(package_name: str) -> None:
    package = importlib.import_module(package_name)
    names = package._NAMES
    eager = set(package.__all__) - set(names)  # defined by the package itself (a version, ...)
    assert set(names) <= set(package.__all__) and all(name in vars(package) for name in eager)
    for name, module in names.items():
        assert getattr(package, name) is getattr(importlib.import_module(module), name), name
    assert set(package.__all__) <= set(dir(package))


@pytest.mark.parametrize("package_name", LAZY_PACKAGES)
def test_an_unknown_name_is_an_attribute_error(package_name: str) -> None:
    package = importlib.import_module(package_name)
    with pytest.raises(AttributeError, match="no_such_name"):
        package.no_such_name  # noqa: B018


def test_importing_the_packages_loads_no_engine() -> None:
    probe = (
        "import sys, frontier_rl, frontier_rl.policies, frontier_rl.swarm, frontier_rl.policies.spec;"
        "print(sorted(n for n in ('numba', 'scipy', 'torch', 'gymnasium') if n in sys.modules))"
    )
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=60, check=True)
    assert done.stdout.strip() == "[]"
