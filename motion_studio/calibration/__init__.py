"""Calibration of our simulator against real rcssserver3d recordings: traces, open-loop replays, agreement, fit."""
