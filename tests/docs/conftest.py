"""The documentation site's tests import the site's Sphinx extensions (docs/_ext) as modules.

The modules that build the site or import its extensions need the ``docs`` extra (Sphinx, MyST,
furo); without it they are skipped, with the reason, and the others (the python blocks, the command
lines, the README, the experiment-files page) still run on ``pip install -e .[dev]``.
"""

from __future__ import annotations

import functools
import importlib
import sys
from pathlib import Path

import pytest

EXTENSIONS = Path(__file__).resolve().parents[2] / "docs" / "_ext"
if str(EXTENSIONS) not in sys.path:
    sys.path.insert(0, str(EXTENSIONS))

DOCS_EXTRA = ("sphinx", "myst_parser", "furo")
"""The packages of the ``docs`` extra (pyproject.toml)."""
NEEDS_DOCS_EXTRA = ("test_extensions.py", "test_generated_pages.py", "test_links.py", "test_site_browser.py")
"""The test modules of this folder that import Sphinx or MyST, or build the site."""


@functools.cache
def missing_docs_extra() -> tuple[str, ...]:
    """The packages of the ``docs`` extra that cannot be imported (the modules that need them import
    them anyway: trying costs nothing)."""
    missing = []
    for name in DOCS_EXTRA:
        try:
            importlib.import_module(name)
        except ImportError:
            missing.append(name)
    return tuple(missing)


class _NeedsDocsExtra(pytest.Module):
    """A test module that is not imported: the docs extra it needs is missing."""

    def collect(self) -> list[pytest.Item]:
        missing = ", ".join(missing_docs_extra())
        pytest.skip(f"{self.path.name} needs the docs extra ({missing} missing): pip install -e '.[docs]'")


def pytest_pycollect_makemodule(module_path: Path, parent: pytest.Collector) -> pytest.Module | None:
    if module_path.name in NEEDS_DOCS_EXTRA and missing_docs_extra():
        return _NeedsDocsExtra.from_parent(parent, path=module_path)
    return None
