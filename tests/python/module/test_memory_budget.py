"""Python entry points hold what they allocate to the memory budget before they allocate (the class of the
program's --memory-budget, icobrdf/pipeline/resource_estimate.hpp): MemoryError with one line naming the call
and what to reduce, and nothing allocated. Sizes are derived here from the cell counts 10 4^L + 2^(L+1)."""
import pytest

import icobrdf


def cells(level):
    return 10 * 4**level + 2 ** (level + 1)


@pytest.fixture
def budget():
    yield icobrdf.set_memory_budget
    icobrdf.set_memory_budget(0)  # measuring again for the other tests


def test_budget_is_set_and_restored(budget):
    budget("300MB")
    assert icobrdf.available_memory() == pytest.approx(300e6)
    budget(0)
    assert icobrdf.available_memory() != pytest.approx(300e6)


def test_lut_beyond_the_budget_raises_before_sampling(budget):
    grid = icobrdf.Grid.equal_area(4)  # 2,592 cells: a LUT of 8 x 2592^2 = 53.7 MB
    assert grid.cells == cells(4)
    budget("40MB")
    with pytest.raises(MemoryError, match=r"lut\(model:lambert\) on a grid of 2592 cells needs about 53.7 MB"):
        icobrdf.lut("model:lambert", grid)
    budget("80MB")
    assert icobrdf.lut("model:lambert", grid)[0].shape == (cells(4), cells(4))


def test_sampler_grid_and_basis_beyond_the_budget_raise(budget):
    budget("50MB")
    with pytest.raises(MemoryError, match=r"Sampler\(model:lambert.*\) at level 6 .*level 5 fits"):
        icobrdf.Sampler(icobrdf.Source("model:lambert"), level=6)
    with pytest.raises(MemoryError, match=r"Grid.equal_area\(7\)"):
        icobrdf.Grid.equal_area(7)  # 163,968 cells of about 3 kB while built
    small = icobrdf.Grid.equal_area(2)
    with pytest.raises(MemoryError, match=r"DiscreteBasis of order 120 on 168 cells"):
        icobrdf.DiscreteBasis(small, 120)  # M = 7,381 modes: an M x M Gram sum alone is 436 MB
