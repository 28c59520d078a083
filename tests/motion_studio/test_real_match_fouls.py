"""Referee fouls counted from a real-server monitor log (motion_studio.realserver.match_figures): the server sends a
foul record per cycle while a robot is being moved, so a burst of records of one player and type is one foul."""

from __future__ import annotations

from pathlib import Path

from motion_studio.realserver.match_figures import _fouls, format_fouls


def _log(tmp_path: Path, frames: list[tuple[float, list[str]]]) -> Path:
    path = tmp_path / "real_monitor.log"
    path.write_text("\n".join(f"((time {t:.2f})(GS (t {t:.2f}){''.join(fouls)}))" for t, fouls in frames) + "\n")
    return path


def test_a_burst_of_records_is_one_foul_and_each_record_counts_once(tmp_path: Path) -> None:
    # measured on the real server: 26 charging records of one robot within 0.5 s (11 v 11, 600 s); every frame
    # repeats the records so far, each with its index
    records = [f"(foul {i} 6 2 9)" for i in range(1, 27)]
    frames = [(263.0 + 0.02 * i, records[: i + 1]) for i in range(26)]
    frames += [(300.0, records + ["(foul 27 6 2 9)"]),                       # the same robot again, later
               (300.02, records + ["(foul 27 6 2 9)", "(foul 28 6 1 4)"]),  # another robot, same type
               (300.04, records + ["(foul 27 6 2 9)", "(foul 28 6 1 4)", "(foul 29 1 1 4)"])]  # another type
    fouls = _fouls(_log(tmp_path, frames), until_s=600.0)
    assert fouls == {"charging": (3, 28), "touching": (1, 1)}
    assert format_fouls(fouls) == "charging 3 (28 records), touching 1"


def test_records_after_the_match_time_and_no_fouls(tmp_path: Path) -> None:
    path = _log(tmp_path, [(10.0, ["(foul 1 1 1 2)"]), (130.0, ["(foul 1 1 1 2)", "(foul 2 6 2 3)"])])
    assert _fouls(path, until_s=120.0) == {"touching": (1, 1)}
    assert format_fouls({}) == "-"
