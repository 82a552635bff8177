"""Build the vendored ROS 2 interface packages ``nav2_msgs`` (NavigateToPose and FollowPath only) and ``tf2_msgs``
(TFMessage only) into this virtual environment.

Neither Nav2's ``nav2_msgs`` nor geometry2's ``tf2_msgs`` has a wheel on PyPI, so the ``NavigateToPose`` and
``FollowPath`` actions and the ``TFMessage`` of ``/tf`` are generated here from their vendored interface files
(``frontier_rl/ros2/interfaces``, copied unchanged from navigation2 and geometry2 so that the DDS type hashes match
ROS 2's) with the rosidl and ament_cmake wheels that ``make`` installs into the venv.

Run it with the venv's interpreter (the venv is ``sys.prefix``)::

    .venv/bin/python tools/build_ros2_interfaces.py

It configures and builds in ``<venv>/ros2_build`` and installs into the venv's own prefix, where the ROS 2 wheels put
their files too: the Python package lands in the venv's site-packages and the libraries in ``<venv>/lib`` (which
the ``ros_wheels_bootstrapper`` that rclpy's wheels install puts on the library path of every venv interpreter), and
the libraries also carry an RPATH to ``<venv>/lib``. So ``from nav2_msgs.action import NavigateToPose`` works in a
fresh process without any environment variable. A second run with unchanged inputs is a no-op (per package). Only
the standard library is used. Success prints a line per package; a failure prints the tail of the build log and exits
non-zero.
"""

from __future__ import annotations

import argparse
import hashlib
import importlib.metadata
import importlib.util
import os
import re
import shutil
import subprocess
import sys
import sysconfig
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
INTERFACES = REPO / "frontier_rl" / "ros2" / "interfaces"
LOG_TAIL_LINES = 40


@dataclass(frozen=True)
class InterfacePackage:
    """A vendored interface package: its name, the interface it holds, the generated Python module that shows it is
    installed (relative to the package in site-packages), and what the verification runs in a clean process: the
    interface and the C type support that rclpy loads (without starting rclpy, so no network is touched)."""

    name: str
    interface: str
    python_module: str
    verify_code: str

    @property
    def source(self) -> Path:
        return INTERFACES / self.name


PACKAGES = (
    InterfacePackage(
        "nav2_msgs",
        "NavigateToPose, FollowPath",
        "action/_follow_path.py",
        "from nav2_msgs.action import FollowPath, NavigateToPose\n"
        "for action in (NavigateToPose, FollowPath):\n"
        "    action.Goal(); action.Result(); action.Feedback()\n"
        "    type(action).__import_type_support__()\n"
        "    assert action._TYPE_SUPPORT is not None\n",
    ),
    InterfacePackage(
        "tf2_msgs",
        "TFMessage",
        "msg/_tf_message.py",
        "from tf2_msgs.msg import TFMessage\n"
        "TFMessage()\n"
        "type(TFMessage).__import_type_support__()\n"
        "assert TFMessage._TYPE_SUPPORT is not None\n",
    ),
)
# The build machine's paths that the message wheels' CMake exports name (the manylinux image's Python)
BUILD_MACHINE_PYTHON_INCLUDE = re.compile(r"/opt/python/cp3\d+-cp3\d+/include/python3\.\d+")
BUILD_MACHINE_NUMPY_INCLUDE = re.compile(
    r"/opt/python/cp3\d+-cp3\d+/lib/python3\.\d+/site-packages/numpy/(?:_core|core)/include"
)


class BuildError(Exception):
    """A step failed; ``log`` names the file whose tail explains why, if any."""

    def __init__(self, message: str, log: Path | None = None) -> None:
        super().__init__(message)
        self.log = log


def find_toolchain() -> tuple[str, str, str]:
    """Return the paths of cmake, a C compiler and a C++ compiler, or raise a one-line error naming what is missing."""
    cmake = shutil.which("cmake")
    c_compiler = shutil.which(os.environ.get("CC", "")) or shutil.which("cc") or shutil.which("gcc")
    cxx_compiler = (
        shutil.which(os.environ.get("CXX", "")) or shutil.which("c++") or shutil.which("g++") or shutil.which("clang++")
    )
    missing = [
        name
        for name, found in (("cmake", cmake), ("a C compiler", c_compiler), ("a C++ compiler", cxx_compiler))
        if not found
    ]
    if missing or cmake is None or c_compiler is None or cxx_compiler is None:
        raise BuildError(
            f"{', '.join(missing)} not found: building the ROS 2 interfaces needs cmake and a C/C++ compiler "
            "(Debian: apt-get install cmake g++)"
        )
    return cmake, c_compiler, cxx_compiler


def source_files(source: Path) -> list[Path]:
    """Return the vendored package's files in a stable order."""
    return sorted(p for p in source.rglob("*") if p.is_file() and "__pycache__" not in p.parts)


def input_digest(source: Path, prefix: Path) -> str:
    """Hash what the build depends on: the vendored files, this script, the interpreter and the ROS wheels' versions."""
    digest = hashlib.sha256()
    for path in [*source_files(source), Path(__file__).resolve()]:
        digest.update(str(path.relative_to(REPO)).encode())
        digest.update(hashlib.sha256(path.read_bytes()).digest())
    digest.update(f"{sys.version}\n{prefix}\n".encode())
    ros_wheels = sorted(
        f"{dist.metadata['Name']}=={dist.version}"
        for dist in importlib.metadata.distributions()
        if (dist.metadata["Name"] or "").lower().startswith("ros-")
    )
    digest.update("\n".join(ros_wheels).encode())
    return digest.hexdigest()


def installed_files(package: InterfacePackage, prefix: Path) -> list[Path]:
    """Return files whose presence shows ``package`` is installed in ``prefix``."""
    site = Path(sysconfig.get_path("purelib", vars={"base": str(prefix), "platbase": str(prefix)}))
    return [
        site / package.name / package.python_module,
        prefix / "lib" / f"lib{package.name}__rosidl_typesupport_c.so",
        prefix / "share" / package.name / "package.xml",
    ]


def fix_cmake_exports(prefix: Path) -> int:
    """Point the wheels' CMake exports at this machine's Python and NumPy headers; return how many files changed.

    The message wheels were built in a manylinux image, and their ``*__rosidl_generator_pyExport.cmake`` name that
    image's include directories, which do not exist here. Rewriting is idempotent: a fixed file has nothing to match.
    """
    python_include = sysconfig.get_paths()["include"]
    numpy_include = numpy_include_dir()
    changed = 0
    for path in sorted(prefix.glob("share/*/cmake/*.cmake")):
        text = path.read_text(encoding="utf-8")
        if "/opt/python/" not in text:
            continue
        fixed = BUILD_MACHINE_NUMPY_INCLUDE.sub(lambda _: numpy_include, text)
        fixed = BUILD_MACHINE_PYTHON_INCLUDE.sub(lambda _: python_include, fixed)
        if fixed != text:
            path.write_text(fixed, encoding="utf-8")
            changed += 1
    return changed


def numpy_include_dir() -> str:
    """Return NumPy's C header directory, asked of this interpreter in a subprocess (NumPy is not imported here)."""
    result = subprocess.run(
        [sys.executable, "-c", "import numpy; print(numpy.get_include())"],
        capture_output=True,
        text=True,
        check=False,
    )
    if result.returncode != 0:
        raise BuildError(f"NumPy is needed to build the ROS 2 interfaces: {result.stderr.strip().splitlines()[-1:]}")
    return result.stdout.strip()


def run_logged(command: Sequence[str], env: Mapping[str, str], log: Path, what: str) -> None:
    """Run ``command`` appending its output to ``log``; raise a ``BuildError`` naming ``what`` if it fails."""
    with log.open("a", encoding="utf-8") as out:
        out.write(f"\n$ {' '.join(command)}\n")
        out.flush()
        result = subprocess.run(command, stdout=out, stderr=subprocess.STDOUT, env=dict(env), check=False)
    if result.returncode != 0:
        raise BuildError(f"{what} failed (exit {result.returncode})", log)


def build(package: InterfacePackage, prefix: Path, build_dir: Path, log: Path) -> None:
    """Configure, build and install ``package`` into ``prefix`` with the venv's ament/rosidl wheels."""
    cmake, c_compiler, cxx_compiler = find_toolchain()
    fix_cmake_exports(prefix)
    build_dir.mkdir(parents=True, exist_ok=True)
    log.write_text(f"building {package.source} into {prefix}\n", encoding="utf-8")
    env = dict(os.environ)
    env.update(
        {
            # the ament index and the CMake packages of the wheels live in the venv's prefix
            "AMENT_PREFIX_PATH": str(prefix),
            "CMAKE_PREFIX_PATH": str(prefix),
            "PATH": os.pathsep.join([str(Path(sys.executable).parent), env.get("PATH", os.defpath)]),
        }
    )
    lib_dir = prefix / "lib"
    run_logged(
        [
            cmake,
            "-S",
            str(package.source),
            "-B",
            str(build_dir),
            f"-DCMAKE_INSTALL_PREFIX={prefix}",
            "-DCMAKE_BUILD_TYPE=Release",
            f"-DCMAKE_C_COMPILER={c_compiler}",
            f"-DCMAKE_CXX_COMPILER={cxx_compiler}",
            f"-DPython3_EXECUTABLE={sys.executable}",
            "-DBUILD_TESTING=OFF",
            # the installed libraries and extension modules find each other and the wheels' libraries in <venv>/lib;
            # DT_RPATH rather than DT_RUNPATH, because only DT_RPATH also serves the wheels' own dependencies (they
            # carry no search path of their own) when nothing has put <venv>/lib on the library path
            f"-DCMAKE_INSTALL_RPATH={lib_dir}",
            "-DCMAKE_SHARED_LINKER_FLAGS=-Wl,--disable-new-dtags",
            "-DCMAKE_MODULE_LINKER_FLAGS=-Wl,--disable-new-dtags",
        ],
        env,
        log,
        "cmake configure",
    )
    jobs = str(max(1, os.cpu_count() or 1))
    run_logged([cmake, "--build", str(build_dir), "--target", "install", "--parallel", jobs], env, log, "cmake build")


def verify(package: InterfacePackage, prefix: Path) -> None:
    """Import the package's interface and its C type support in a fresh interpreter with an empty environment."""
    result = subprocess.run(
        [sys.executable, "-c", package.verify_code],
        capture_output=True,
        text=True,
        env={},
        cwd=prefix,
        check=False,
    )
    if result.returncode != 0:
        tail = "\n".join((result.stdout + result.stderr).strip().splitlines()[-LOG_TAIL_LINES:])
        hint = ""
        if importlib.util.find_spec("ros_wheels_bootstrapper") is None:
            # it puts <venv>/lib on the library path of every venv interpreter; the message wheels rely on it
            hint = " (the ROS 2 runtime wheels are missing: install ros-kilted-rclpy and ros-kilted-rmw-fastrtps-cpp)"
        raise BuildError(f"the built {package.name} does not import in a clean environment{hint}:\n{tail}")


def print_log_tail(log: Path) -> None:
    """Print the last lines of the build log to stderr."""
    if not log.is_file():
        return
    lines = log.read_text(encoding="utf-8", errors="replace").splitlines()
    print(f"--- last {min(len(lines), LOG_TAIL_LINES)} lines of {log} ---", file=sys.stderr)
    print("\n".join(lines[-LOG_TAIL_LINES:]), file=sys.stderr)


def parse_args(argv: Sequence[str] | None) -> argparse.Namespace:
    """Parse the command line."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--force", action="store_true", help="rebuild even when the inputs are unchanged")
    return parser.parse_args(argv)


def main(argv: Sequence[str] | None = None) -> int:
    """Build, install and verify each vendored package unless it is up to date; return the exit status."""
    args = parse_args(argv)
    prefix = Path(sys.prefix)
    if prefix == Path(sys.base_prefix):
        print(f"error: run this with a virtual environment's python, not {sys.executable}", file=sys.stderr)
        return 2
    for package in PACKAGES:
        status = build_package(package, prefix, args.force)
        if status:
            return status
    return 0


def build_package(package: InterfacePackage, prefix: Path, force: bool) -> int:
    """Build, install and verify ``package`` unless it is up to date; return the exit status."""
    build_dir = prefix / "ros2_build" / package.name
    stamp = build_dir / f"{package.name}.stamp"
    log = build_dir / "build.log"
    digest = input_digest(package.source, prefix)
    up_to_date = (
        stamp.is_file()
        and stamp.read_text(encoding="utf-8").strip() == digest
        and all(path.is_file() for path in installed_files(package, prefix))
    )
    if up_to_date and not force:
        print(f"{package.name} ({package.interface}) is up to date in {prefix}")
        return 0
    started = time.monotonic()
    try:
        stamp.unlink(missing_ok=True)
        build(package, prefix, build_dir, log)
        verify(package, prefix)
    except BuildError as error:
        print(f"error: {error}", file=sys.stderr)
        if error.log is not None:
            print_log_tail(error.log)
        return 1
    stamp.write_text(digest + "\n", encoding="utf-8")
    took = time.monotonic() - started
    print(f"{package.name} ({package.interface}) built and installed into {prefix} in {took:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
