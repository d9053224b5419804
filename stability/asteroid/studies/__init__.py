"""The asteroid family's study kind: :mod:`.tumbler` (an ensemble over a tumbler's uncertain
moment ratios and periods). Registered in :data:`stability.study.STUDIES` from the family's
``STUDIES``."""
