"""The terminal summaries' building blocks (planner.core.text): aligned tables, ``key value`` lines, and notes
that differ only in the names they mention folded into one line with a count."""

from __future__ import annotations

import pytest

from planner.core.text import fold_alike, key_values, natural_key, or_none, table, yes_no


def test_table_columns_are_as_wide_as_their_content_and_numbers_right_aligned() -> None:
    # widths from the widest cell (header included); the numeric columns end in one column, the words start in one
    lines = table(
        ["zone", "side", "stations", "worst e"], [("Z1", "inside", 1, "4.06 mm"), ("outline", "outside", 12, "")]
    )
    assert lines == [
        "  zone     side     stations  worst e",
        "  Z1       inside          1  4.06 mm",
        "  outline  outside        12",
    ]


def test_table_cells_are_words_a_person_writes() -> None:
    # None, True/False and big ints as a person writes them, never as Python reprs
    (_, row) = table(["a", "b", "c", "d"], [(None, True, False, 12345)], indent="")
    assert row.split() == ["none", "yes", "no", "12,345"]


def test_table_refuses_a_row_of_another_length() -> None:
    with pytest.raises(ValueError, match="every row needs 2 cells"):
        table(["a", "b"], [("x",)])


def test_key_values_align_the_values() -> None:
    assert key_values([("candidates", 1058), ("forced", None), ("connected", True)]) == [
        "  candidates  1,058",
        "  forced      none",
        "  connected   yes",
    ]
    assert yes_no(False) == "no" and or_none(None) == "none" and or_none(2.5, ".2f") == "2.50"


def test_natural_order_of_names() -> None:
    assert sorted(["CP10", "CP2", "CP1.10", "CP1.2", "Z11", "Z1"], key=natural_key) == [
        "CP1.2",
        "CP1.10",
        "CP2",
        "CP10",
        "Z1",
        "Z11",
    ]


def test_notes_that_differ_only_in_names_are_folded_with_a_count() -> None:
    # the network check's datum notes, one per network part in the parts' order: one line, at the place of the
    # first, showing the part whose name comes first and the count with the names that differ
    datum = [
        f"datum of the network part holding CP{k}: CP{k}.1, CP{k}.2, CP{k}.3 held fixed"
        for k in (4, 5, 6, 7, 8, 9, 1, 10, 2, 11, 12, 3)
    ]
    notes = ["control traverse: 90 legs", *datum, "no control point has a height"]
    assert fold_alike(notes) == [
        "control traverse: 90 legs",
        "datum of the network part holding CP1: CP1.1, CP1.2, CP1.3 held fixed "
        "(same for 12: CP1, CP2, CP3, CP4, CP5, ..., CP12)",
        "no control point has a height",
    ]


def test_notes_that_differ_in_a_measured_value_stay_apart() -> None:
    # a bare number is a measurement, not a name: 4.5 m and 4.8 m are two facts, not one
    notes = [
        "control points of Z8-in-C are only 4.5 m apart",
        "control points of Z9-in-C are only 4.8 m apart",
        "control points of Z10-in-C are only 4.5 m apart",
    ]
    assert fold_alike(notes) == [
        "control points of Z8-in-C are only 4.5 m apart (same for 2: Z8-in-C, Z10-in-C)",
        "control points of Z9-in-C are only 4.8 m apart",
    ]


def test_names_without_digits_fold_when_given_and_identical_notes_are_counted() -> None:
    # zone names such as "outline" or "house" hold no digit: they are names only where the caller says so
    notes = ["no spot fits in house", "no spot fits in garage", "heights: plan only", "heights: plan only"]
    assert fold_alike(notes) == notes[:2] + ["heights: plan only (2 times)"]
    assert fold_alike(notes, ["house", "garage"])[0] == "no spot fits in garage (same for 2: garage, house)"
