"""The time ledger: seconds by stage for the run under way, nothing outside one."""

import pytest

from stability.util.ledger import STAGES, book, time_ledger


def test_a_ledger_adds_up_what_is_booked_inside_it_and_nothing_outside():
    book("integration", 5.0)  # no ledger open: nothing kept anywhere
    with time_ledger() as outer:
        book("integration", 1.5)
        book("integration", 0.25)
        with time_ledger() as inner:
            book("figures", 2.0)
        book("write", 0.5)
    assert dict(outer) == {"integration": 1.75, "write": 0.5}
    assert dict(inner) == {"figures": 2.0}
    with time_ledger() as again:
        pass
    assert dict(again) == {}


def test_an_unknown_stage_is_refused_in_one_line():
    with pytest.raises(ValueError) as caught:
        book("plotting", 1.0)
    assert str(caught.value) == f"stage must be one of {', '.join(STAGES)}, got 'plotting'"
