"""Allows ``python -m motion_studio``."""

from motion_studio.cli import main

main()
