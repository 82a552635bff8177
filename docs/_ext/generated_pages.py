"""Pages generated from the code when the build starts (Sphinx's ``builder-inited``).

Every generator is listed once, in :data:`GENERATORS`: a module of ``docs/_ext`` with a function
``generate(out_dir: Path) -> None`` that writes Markdown (and pictures) into an empty folder, and the
folder under ``docs/`` that receives them. The module is imported when it runs, so that reading the
list is cheap (the tests read it). That folder is generated whole (the build deletes what the generator no longer
writes) and is ignored by git. A file whose content did not change is left untouched, so that
Sphinx rebuilds only the pages that did.
"""

from __future__ import annotations

import filecmp
import importlib
import shutil
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from sphinx.application import Sphinx
from sphinx.errors import ExtensionError
from sphinx.util import logging

LOGGER = logging.getLogger(__name__)


@dataclass(frozen=True)
class Generator:
    """A generator of pages: the folder (relative to ``docs/``) it fills, and the module of
    ``docs/_ext`` whose ``generate(out_dir)`` fills it."""

    folder: str
    module: str

    def generate(self, out_dir: Path) -> None:
        """Write this generator's files into the empty folder ``out_dir``."""
        importlib.import_module(self.module).generate(out_dir)


GENERATORS: tuple[Generator, ...] = (
    Generator("_generated/cli", "cli_reference"),
    Generator("_generated/config", "config_reference"),
    Generator("reference/envs", "env_pages"),
    Generator("results/pages", "results_pages"),
    Generator("_generated/architecture", "architecture_layers"),
)
"""Every generator of the site, run in this order."""


def run_generators(app: Sphinx) -> None:
    """Run every generator of :data:`GENERATORS` into its folder under the source folder."""
    for generator in GENERATORS:
        started = time.perf_counter()
        target = Path(app.srcdir) / generator.folder
        with tempfile.TemporaryDirectory() as staging:
            try:
                generator.generate(Path(staging))
            except Exception as exc:
                raise ExtensionError(f"generating {generator.folder}/ failed: {exc}", exc) from exc
            changed = sync_folder(Path(staging), target)
        seconds = time.perf_counter() - started
        LOGGER.info(f"[generated] {generator.folder}/: {changed} file(s) changed in {seconds:.1f} s")


def sync_folder(source: Path, target: Path) -> int:
    """Make ``target`` hold what ``source`` holds, copying only the files that differ; returns how
    many files were written or removed."""
    target.mkdir(parents=True, exist_ok=True)
    wanted = {p.relative_to(source) for p in source.rglob("*") if p.is_file()}
    changed = 0
    for stale in sorted(p for p in target.rglob("*") if p.is_file() and p.relative_to(target) not in wanted):
        stale.unlink()
        changed += 1
    for relative in sorted(wanted):
        destination = target / relative
        if destination.is_file() and filecmp.cmp(source / relative, destination, shallow=False):
            continue
        destination.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(source / relative, destination)
        changed += 1
    return changed


def setup(app: Sphinx) -> dict[str, Any]:
    app.connect("builder-inited", run_generators)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
