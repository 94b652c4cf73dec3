"""pim/model/numba_cache.py: the cache key covers the extra source files."""

import hashlib

from numba import njit

from pim.model import formula, tyres
from pim.model.numba_cache import cache_stamp, files_stamp, stamped_cache


def test_stamp_is_the_sha256_of_the_files():
    want = hashlib.sha256(open(formula.__file__, "rb").read()
                          + open(tyres.__file__, "rb").read()).hexdigest()
    assert files_stamp(formula, tyres) == want


def test_the_dispatcher_key_holds_the_stamp():
    @stamped_cache(tyres)
    @njit(cache=True)
    def twice(x):  # pragma: no cover - compiled
        return 2.0 * x

    assert twice(2.0) == 4.0
    own, extra = cache_stamp(twice)
    assert extra == files_stamp(tyres) and own
