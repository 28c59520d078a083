"""The tuning room's files: the one writer of tuned values keeps every other section byte for byte, refuses
(and undoes) a section its loader rejects, and writes provenance; rollouts-to-target is read from a trace."""

from __future__ import annotations

import tomllib

import pytest

from motion_studio.tuning import TuningError
from motion_studio.tuning.compare import rollouts_to_target
from motion_studio.tuning.params_file import Provenance, git_revision, replace_sections, section_text, write_sections

TEXT = """# Header: units in the key names.
# Made by hand.

[common]
a_m = 1.0  # kept

[kick]
b_deg = 2.0

[[kick.phase]]
c_ms = 40

[kick_strong]
b_deg = 3.0
"""


def test_a_section_and_its_sub_tables_are_replaced_and_the_rest_kept_byte_for_byte():
    new = replace_sections(TEXT, {"kick": section_text("kick", {"provenance": "p", "b_deg": 2.5})})
    assert new.startswith(TEXT.split("[kick]")[0])
    assert new.endswith("[kick_strong]\nb_deg = 3.0\n")
    data = tomllib.loads(new)
    assert data["kick"] == {"provenance": "p", "b_deg": 2.5} and data["common"] == {"a_m": 1.0}
    appended = replace_sections(TEXT, {"kick_left": section_text("kick_left", {"b_deg": 1.0})})
    assert appended.startswith(TEXT.rstrip("\n")) and tomllib.loads(appended)["kick_left"] == {"b_deg": 1.0}


def test_a_rewrite_the_loader_refuses_is_undone_and_named(tmp_path):
    path = tmp_path / "kick.toml"
    path.write_text(TEXT)

    def check(written):
        if tomllib.loads(written.read_text())["kick"]["b_deg"] < 0:
            raise ValueError("[kick] b_deg must be >= 0")

    with pytest.raises(TuningError, match=r"kick.toml: the rewritten file does not load \(\[kick\] b_deg must be >= 0\)"):
        write_sections(path, {"kick": section_text("kick", {"b_deg": -1.0})}, check)
    assert path.read_text() == TEXT
    write_sections(path, {"kick": section_text("kick", {"b_deg": 1.5})}, check)
    assert tomllib.loads(path.read_text())["kick"] == {"b_deg": 1.5}


def test_provenance_names_command_date_and_revision():
    provenance = Provenance.now(["motion-studio", "tune", "lean", "--evaluations", "40"])
    text = provenance.text("curvature within 1.2 deg/m")
    assert text.startswith("curvature within 1.2 deg/m; motion-studio tune lean --evaluations 40 on 20")
    revision = git_revision()
    assert text.endswith(f" at {revision}") and revision != ""


def test_rollouts_to_target_counts_in_evaluation_order():
    records = [{"kind": "run", "rollouts_per_candidate": 4},
               {"kind": "evaluation", "iteration": 0, "index": 1, "loss": 1.0},
               {"kind": "evaluation", "iteration": -1, "index": 0, "loss": 5.0},
               {"kind": "evaluation", "iteration": 0, "index": 0, "loss": 3.0},
               {"kind": "evaluation", "iteration": 1, "index": 0, "loss": 0.5}]
    assert rollouts_to_target(records, 3.0) == 8  # the start, then candidate 0 of iteration 0
    assert rollouts_to_target(records, 1.0) == 12
    assert rollouts_to_target(records, 0.1) is None
