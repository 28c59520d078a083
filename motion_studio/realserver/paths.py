"""Where the real server lives: its scripts (build.sh, server.sh, netns.sh) and its install prefix.

Paths are relative to the project: the scripts are found at ``<project>/../shared/real-server`` unless the
environment variable ``NAO3D_REAL_SERVER_DIR`` (or a command's option) says otherwise; the install prefix is
``/tmp/ss/install`` unless ``SS_PREFIX`` says otherwise, as ``server.sh`` reads it.
"""

from __future__ import annotations

import os
from pathlib import Path

from motion_studio.realserver.errors import RealServerError

#: The project's root folder (the one holding kinematics/, sim/, motion_studio/ ...).
PROJECT_DIR = Path(__file__).resolve().parents[2]
#: Environment variable naming the folder of the real-server scripts.
DIR_VARIABLE = "NAO3D_REAL_SERVER_DIR"
#: server.sh's install prefix variable and its default.
PREFIX_VARIABLE = "SS_PREFIX"
DEFAULT_PREFIX = Path("/tmp/ss/install")
SCRIPTS = ("server.sh", "netns.sh")


def default_scripts_dir() -> Path:
    """``<project>/../shared/real-server``."""
    return PROJECT_DIR.parent / "shared" / "real-server"


def scripts_dir(option: Path | None = None) -> Path:
    """The real-server scripts folder: ``option``, else ``$NAO3D_REAL_SERVER_DIR``, else the default."""
    if option is not None:
        return Path(option).resolve()
    named = os.environ.get(DIR_VARIABLE)
    return Path(named).resolve() if named else default_scripts_dir()


def install_prefix() -> Path:
    """The install prefix of the built server (``$SS_PREFIX`` or /tmp/ss/install)."""
    return Path(os.environ.get(PREFIX_VARIABLE) or DEFAULT_PREFIX)


def server_binary() -> Path:
    """``<prefix>/bin/rcssserver3d``."""
    return install_prefix() / "bin" / "rcssserver3d"


def installed() -> bool:
    """Whether the real server has been built (its rcssserver3d binary exists)."""
    return server_binary().is_file()


def checked_scripts_dir(option: Path | None = None) -> Path:
    """The scripts folder, checked to hold server.sh and netns.sh.

    Raises:
        RealServerError: a script is missing (the folder and the variable or option to set are named).
    """
    folder = scripts_dir(option)
    missing = [name for name in SCRIPTS if not (folder / name).is_file()]
    if missing:
        raise RealServerError(f"no {' or '.join(missing)} in {folder} (set {DIR_VARIABLE} or --real-server-dir "
                              "to the folder of the real-server scripts)")
    return folder


def build_hint(option: Path | None = None) -> str:
    """The one line telling how to build the real server."""
    script = scripts_dir(option) / "build.sh"
    try:
        shown = os.path.relpath(script)
    except ValueError:
        shown = str(script)
    return (f"the real server is not built ({server_binary()} missing): "
            f"bash {shown} <git dir of BerlinUnited/SimSpark-SPL>")
