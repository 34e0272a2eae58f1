#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "armkit/reach.hpp"
#include "bindings.hpp"

namespace armkit::bindings {

namespace {

using OutCount = nb::ndarray<std::int64_t, nb::c_contig, nb::device::cpu>;

VoxelGrid make_grid(In lower, double resolution, std::int64_t nx, std::int64_t ny, std::int64_t nz,
                    const OutCount& hits) {
    if (lower.size() != 3 || !(resolution > 0.0) || nx < 1 || ny < 1 || nz < 1)
        throw std::invalid_argument("grid: expected lower (3,), resolution > 0 and a positive shape");
    VoxelGrid grid{{lower.data()[0], lower.data()[1], lower.data()[2]}, resolution, {nx, ny, nz}};
    if (hits.size() != std::size_t(grid.size()))
        throw std::invalid_argument("hits: expected one counter per voxel (nx * ny * nz)");
    return grid;
}

void check_box(const Chain& chain, const In& low, const In& high) {
    if (low.size() != std::size_t(chain.n) || high.size() != std::size_t(chain.n))
        throw std::invalid_argument("box: expected low and high (n,)");
}

std::int64_t reach_uniform(const Chain& chain, In low, In high, std::uint64_t seed, std::uint64_t first,
                           std::size_t count, In lower, double resolution, std::int64_t nx, std::int64_t ny,
                           std::int64_t nz, OutCount hits, int threads) {
    check_box(chain, low, high);
    const VoxelGrid grid = make_grid(lower, resolution, nx, ny, nz, hits);
    return count_uniform(chain, low.data(), high.data(), seed, first, count, grid, hits.data(), threads);
}

std::int64_t reach_given(const Chain& chain, In q, In lower, double resolution, std::int64_t nx,
                         std::int64_t ny, std::int64_t nz, OutCount hits, int threads) {
    if (q.size() % std::size_t(chain.n) != 0) throw std::invalid_argument("q: expected (N, n) joint values");
    const VoxelGrid grid = make_grid(lower, resolution, nx, ny, nz, hits);
    return count_given(chain, q.data(), q.size() / std::size_t(chain.n), grid, hits.data(), threads);
}

void sample(const Chain& chain, In low, In high, std::uint64_t seed, std::uint64_t first, Out q, int threads) {
    check_box(chain, low, high);
    if (q.size() % std::size_t(chain.n) != 0) throw std::invalid_argument("q: expected an (N, n) output");
    sample_uniform(chain.n, low.data(), high.data(), seed, first, q.size() / std::size_t(chain.n), q.data(),
                   threads);
}

}  // namespace

void bind_workspace(nb::module_& m) {
    const auto release = nb::call_guard<nb::gil_scoped_release>();
    m.def("reach_uniform", &reach_uniform, nb::arg("chain"), nb::arg("low"), nb::arg("high"), nb::arg("seed"),
          nb::arg("first"), nb::arg("count"), nb::arg("lower"), nb::arg("resolution"), nb::arg("nx"),
          nb::arg("ny"), nb::arg("nz"), nb::arg("hits"), nb::arg("threads"), release,
          "Adds to hits (nx*ny*nz) the voxels of the tool positions of configurations [first, first + count) "
          "drawn uniformly in [low, high) from seed; returns the samples outside the grid.");
    m.def("reach_given", &reach_given, nb::arg("chain"), nb::arg("q"), nb::arg("lower"), nb::arg("resolution"),
          nb::arg("nx"), nb::arg("ny"), nb::arg("nz"), nb::arg("hits"), nb::arg("threads"), release,
          "Adds to hits the voxels of the tool positions of q (N, n, finite); returns the samples outside.");
    m.def("sample_uniform", &sample, nb::arg("chain"), nb::arg("low"), nb::arg("high"), nb::arg("seed"),
          nb::arg("first"), nb::arg("q"), nb::arg("threads"), release,
          "Configurations [first, first + N) of the batch seeded seed into q (N, n): those reach_uniform draws.");
}

}  // namespace armkit::bindings
