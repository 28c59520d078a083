"""motion_studio: the user's workbench (edit, view, bench, tune, match); nothing imports it."""
