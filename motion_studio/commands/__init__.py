"""Subcommands of motion-studio, one module per job."""
