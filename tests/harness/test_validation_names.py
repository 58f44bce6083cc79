"""Witness file names say who failed on what, once: a replayed witness is named by its file's
stem, not by the implementation twice and the file's suffix in the middle."""

from vorobench.harness.validation import witness_stem


def test_a_generated_case_is_named_by_who_what_and_seed():
    assert witness_stem("my-buggy", "uniform", 10, 0) == "my-buggy-uniform-n10-s0"
    assert witness_stem("my-buggy", "uniform", 10, 0, "integer", "fortune") == \
        "my-buggy-uniform-n10-s0-winteger-vs-fortune"


def test_a_replayed_witness_keeps_its_stem_and_drops_the_repeated_name():
    assert witness_stem("my-buggy", "my-buggy-uniform-n10-s0.npy", 4, None) == "my-buggy-uniform-n10-s0-n4"
    assert witness_stem("x", "pts.txt", 4, None) == "x-pts-n4"
    assert witness_stem("my-buggy", "my-buggy.npy", 3, None) == "my-buggy-my-buggy-n3"   # nothing left to drop
