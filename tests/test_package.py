"""The package's metadata: one version, one licence everywhere, a valid citation, and the
platforms it states are the ones the tests run on."""

from __future__ import annotations

import platform
import subprocess
import sys
import tomllib
import xml.etree.ElementTree as ET
from pathlib import Path

import yaml

import frontier_rl

REPO = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]


def test_the_version_is_written_once_and_the_ros_package_follows_it() -> None:
    assert PYPROJECT["dynamic"] == ["version"]
    assert "version" not in PYPROJECT
    package_xml = ET.parse(REPO / "ros" / "frontier_rl_ros" / "package.xml").getroot()
    assert package_xml.findtext("version") == frontier_rl.__version__
    assert "version" not in yaml.safe_load((REPO / "CITATION.cff").read_text())


def test_one_licence_everywhere() -> None:
    assert (REPO / "LICENSE").read_text().startswith("MIT License")
    assert PYPROJECT["license"] == "MIT"
    package_xml = ET.parse(REPO / "ros" / "frontier_rl_ros" / "package.xml").getroot()
    assert package_xml.findtext("license") == "MIT"
    assert yaml.safe_load((REPO / "CITATION.cff").read_text())["license"] == "MIT"


def test_the_citation_is_valid_and_cites_the_thesis() -> None:
    done = subprocess.run(
        [str(Path(sys.executable).parent / "cffconvert"), "--validate", "-i", str(REPO / "CITATION.cff")],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr
    titles = [ref["title"] for ref in yaml.safe_load((REPO / "CITATION.cff").read_text())["references"]]
    assert "Deep Reinforcement Learning for Intelligent Frontier Ranking in Search-and-rescue Scenarios" in titles


def test_the_stated_platform_is_the_one_tested() -> None:
    """The classifiers name the Python versions and the operating system the suite runs on."""
    classifiers = PYPROJECT["classifiers"]
    stated = {c.rsplit(" :: ", 1)[1] for c in classifiers if c.startswith("Programming Language :: Python :: 3.")}
    assert f"{sys.version_info.major}.{sys.version_info.minor}" in stated
    assert PYPROJECT["requires-python"] == f">={min(stated, key=lambda v: tuple(map(int, v.split('.'))))}"
    assert platform.system() == "Linux" and "Operating System :: POSIX :: Linux" in classifiers
