// perifrac's C shim over the system OpenVDB (MPL-2.0, linked dynamically).
//
// A handful of plain C functions over openvdb::FloatGrid level sets: rasterize
// spheres (tools::ParticlesToLevelSet), make the union a narrow band of signed
// distance (tools::sdfToSdf, tools::LevelSetTracker), filter (tools::LevelSetFilter), mesh
// (tools::volumeToMesh), and gather fragments into one frame (tools::csgUnion plus a
// velocity grid) that is written as a .vdb file. Every C++ exception is caught here
// and returned as a non-zero status with its text in the caller's buffer.
//
// The declarations the Rust side uses are in src/lib.rs; keep the two in step.

#include <openvdb/openvdb.h>
#include <openvdb/tools/ChangeBackground.h>
#include <openvdb/tools/Composite.h>
#include <openvdb/tools/FastSweeping.h>
#include <openvdb/tools/LevelSetFilter.h>
#include <openvdb/tools/ParticlesToLevelSet.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace {

using openvdb::FloatGrid;
using openvdb::Vec3SGrid;
using IndexGrid = FloatGrid::ValueConverter<openvdb::Index32>::Type;

enum Status : int {
    PVDB_OK = 0,
    PVDB_INVALID_ARGUMENT = 1,
    PVDB_OPENVDB_ERROR = 2,
    PVDB_STD_ERROR = 3,
    PVDB_UNKNOWN_ERROR = 4,
};

using Tracker = openvdb::tools::LevelSetTracker<FloatGrid>;
using Filter = openvdb::tools::LevelSetFilter<FloatGrid>;

// First-order upwinding, one Runge-Kutta stage and one renormalization pass: several
// times faster than OpenVDB's defaults (WENO5, RK2, three passes), and the surfaces
// are smoothed afterwards anyway.
template <typename T>
void fast_schemes(T& tracker) {
    tracker.setSpatialScheme(openvdb::math::FIRST_BIAS);
    tracker.setTemporalScheme(openvdb::math::TVD_RK1);
    tracker.setNormCount(1);
}

std::once_flag initialized;
std::mutex thread_limit_lock;
std::unique_ptr<tbb::global_control> thread_limit;

void set_error(char* err, size_t err_len, const std::string& message) {
    if (err != nullptr && err_len > 0) std::snprintf(err, err_len, "%s", message.c_str());
}

// Runs `body`, turning every exception into a status and a message.
template <typename F>
int guarded(char* err, size_t err_len, F&& body) {
    try {
        return body();
    } catch (const openvdb::Exception& e) {
        set_error(err, err_len, e.what());
        return PVDB_OPENVDB_ERROR;
    } catch (const std::exception& e) {
        set_error(err, err_len, e.what());
        return PVDB_STD_ERROR;
    } catch (...) {
        set_error(err, err_len, "unknown C++ exception in OpenVDB");
        return PVDB_UNKNOWN_ERROR;
    }
}

// The particle-list adaptor ParticlesToLevelSet needs: borrows the caller's arrays.
struct ParticleList {
    using PosType = openvdb::Vec3R;
    const float* positions;  // 3 per particle
    const float* radii;      // 1 per particle
    size_t count;

    size_t size() const { return count; }
    void getPos(size_t n, openvdb::Vec3R& xyz) const {
        xyz = openvdb::Vec3R(positions[3 * n], positions[3 * n + 1], positions[3 * n + 2]);
    }
    void getPosRad(size_t n, openvdb::Vec3R& xyz, openvdb::Real& radius) const {
        getPos(n, xyz);
        radius = radii[n];
    }
    void getPosRadVel(size_t n, openvdb::Vec3R& xyz, openvdb::Real& radius,
                      openvdb::Vec3R& velocity) const {
        getPosRad(n, xyz, radius);
        velocity = openvdb::Vec3R(0.0);
    }
    void getAtt(size_t n, openvdb::Index32& index) const { index = openvdb::Index32(n); }
};

}  // namespace

// A narrow-band level set of one set of particles, with the index of the particle
// that made each voxel of the rasterized band.
struct PvdbLevelSet {
    FloatGrid::Ptr grid;
    IndexGrid::Ptr closest;
};

// A frame: the union of its level sets ("surface") and a velocity grid ("v").
struct PvdbFrame {
    FloatGrid::Ptr surface;
    Vec3SGrid::Ptr velocity;
};

// A mesh from volumeToMesh: points, triangles and quads.
struct PvdbMesh {
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<openvdb::Vec4I> quads;
};

extern "C" {

void pvdb_initialize(size_t threads) {
    std::call_once(initialized, [] { openvdb::initialize(); });
    std::lock_guard<std::mutex> guard(thread_limit_lock);
    thread_limit.reset();
    if (threads > 0) {
        thread_limit = std::make_unique<tbb::global_control>(
            tbb::global_control::max_allowed_parallelism, threads);
    }
}

int pvdb_level_set_from_spheres(const float* positions, const float* radii, size_t count,
                                double voxel_size, double half_width, PvdbLevelSet** out,
                                size_t* dropped_small, size_t* dropped_large, char* err,
                                size_t err_len) {
    return guarded(err, err_len, [&]() -> int {
        *out = nullptr;
        *dropped_small = 0;
        *dropped_large = 0;
        if (count == 0) {
            set_error(err, err_len, "no particles to rasterize");
            return PVDB_INVALID_ARGUMENT;
        }
        if (!(std::isfinite(voxel_size) && voxel_size > 0.0)) {
            set_error(err, err_len,
                      "the voxel size must be positive and finite, got " +
                          std::to_string(voxel_size));
            return PVDB_INVALID_ARGUMENT;
        }
        if (!(std::isfinite(half_width) && half_width >= 1.0)) {
            set_error(err, err_len,
                      "the narrow band's half width must be at least 1 voxel, got " +
                          std::to_string(half_width));
            return PVDB_INVALID_ARGUMENT;
        }
        for (size_t i = 0; i < count; ++i) {
            const float* p = positions + 3 * i;
            if (!(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]) &&
                  std::isfinite(radii[i]) && radii[i] > 0.0f)) {
                set_error(err, err_len,
                          "particle " + std::to_string(i) +
                              " has a non-finite position or a radius that is not positive");
                return PVDB_INVALID_ARGUMENT;
            }
        }
        // Each sphere writes the voxels within its radius plus the band's half width,
        // the bulk of the cost: rasterize with a band of at most 2 voxels and widen it
        // afterwards.
        const double raster_width = std::min(half_width, 2.0);
        auto grid = openvdb::createLevelSet<FloatGrid>(voxel_size, raster_width);
        openvdb::tools::ParticlesToLevelSet<FloatGrid, openvdb::Index32> raster(*grid);
        const ParticleList list{positions, radii, count};
        raster.rasterizeSpheres(list);
        raster.finalize(true);
        *dropped_small = raster.getMinCount();
        *dropped_large = raster.getMaxCount();
        auto result = std::make_unique<PvdbLevelSet>();
        result->closest = raster.attributeGrid();
        // The raster is a union of spheres whose whole interior is active, holding
        // the distance to the nearest sphere's surface, not to the union's. Fast
        // sweeping solves for the true signed distance on those voxels; trimming
        // then keeps the narrow band, which `resize` widens to the half width asked.
        auto sdf = openvdb::tools::sdfToSdf(*grid, 0.0f, 1);
        sdf->setGridClass(openvdb::GRID_LEVEL_SET);
        // sdfToSdf picks its own background; the band is the raster's.
        openvdb::tools::changeLevelSetBackground(sdf->tree(), float(raster_width * voxel_size));
        Tracker tracker(*sdf);
        fast_schemes(tracker);
        tracker.prune();
        tracker.resize(openvdb::Index(std::lround(half_width)));
        result->grid = sdf;
        *out = result.release();
        return PVDB_OK;
    });
}

void pvdb_level_set_free(PvdbLevelSet* level_set) { delete level_set; }

// kind: 0 mean curvature, 1 Gaussian (width 1), 2 Laplacian.
int pvdb_level_set_filter(PvdbLevelSet* level_set, int kind, size_t iterations, char* err,
                          size_t err_len) {
    return guarded(err, err_len, [&]() -> int {
        if (kind < 0 || kind > 2) {
            set_error(err, err_len, "unknown filter kind " + std::to_string(kind));
            return PVDB_INVALID_ARGUMENT;
        }
        Filter filter(*level_set->grid);
        fast_schemes(filter);
        for (size_t i = 0; i < iterations; ++i) {
            switch (kind) {
                case 0: filter.meanCurvature(); break;
                case 1: filter.gaussian(1); break;
                default: filter.laplacian(); break;
            }
        }
        return PVDB_OK;
    });
}

// Moves the surface outward by `distance` (world units; negative moves it inward).
int pvdb_level_set_offset(PvdbLevelSet* level_set, double distance, char* err,
                          size_t err_len) {
    return guarded(err, err_len, [&]() -> int {
        if (!std::isfinite(distance)) {
            set_error(err, err_len, "the offset must be finite");
            return PVDB_INVALID_ARGUMENT;
        }
        if (distance == 0.0) return PVDB_OK;
        Filter filter(*level_set->grid);
        fast_schemes(filter);
        // LevelSetFilter::offset adds to the distance: a positive value erodes.
        filter.offset(float(-distance));
        return PVDB_OK;
    });
}

int pvdb_level_set_mesh(const PvdbLevelSet* level_set, double adaptivity, PvdbMesh** out,
                        char* err, size_t err_len) {
    return guarded(err, err_len, [&]() -> int {
        *out = nullptr;
        if (!(adaptivity >= 0.0 && adaptivity <= 1.0)) {
            set_error(err, err_len, "adaptivity must be in [0, 1]");
            return PVDB_INVALID_ARGUMENT;
        }
        auto mesh = std::make_unique<PvdbMesh>();
        openvdb::tools::volumeToMesh(*level_set->grid, mesh->points, mesh->triangles,
                                     mesh->quads, 0.0, adaptivity, true);
        *out = mesh.release();
        return PVDB_OK;
    });
}

size_t pvdb_mesh_point_count(const PvdbMesh* mesh) { return mesh->points.size(); }
size_t pvdb_mesh_triangle_count(const PvdbMesh* mesh) { return mesh->triangles.size(); }
size_t pvdb_mesh_quad_count(const PvdbMesh* mesh) { return mesh->quads.size(); }

// Copies the mesh out: 3 floats a point, 3 indices a triangle, 4 a quad.
void pvdb_mesh_copy(const PvdbMesh* mesh, float* points, uint32_t* triangles, uint32_t* quads) {
    for (size_t i = 0; i < mesh->points.size(); ++i) {
        for (int k = 0; k < 3; ++k) points[3 * i + k] = mesh->points[i][k];
    }
    for (size_t i = 0; i < mesh->triangles.size(); ++i) {
        for (int k = 0; k < 3; ++k) triangles[3 * i + k] = mesh->triangles[i][k];
    }
    for (size_t i = 0; i < mesh->quads.size(); ++i) {
        for (int k = 0; k < 4; ++k) quads[4 * i + k] = mesh->quads[i][k];
    }
}

void pvdb_mesh_free(PvdbMesh* mesh) { delete mesh; }

int pvdb_frame_new(double voxel_size, double half_width, PvdbFrame** out, char* err,
                   size_t err_len) {
    return guarded(err, err_len, [&]() -> int {
        *out = nullptr;
        if (!(std::isfinite(voxel_size) && voxel_size > 0.0 && half_width >= 1.0)) {
            set_error(err, err_len, "the voxel size and half width must be positive");
            return PVDB_INVALID_ARGUMENT;
        }
        auto frame = std::make_unique<PvdbFrame>();
        frame->surface = openvdb::createLevelSet<FloatGrid>(voxel_size, half_width);
        frame->surface->setName("surface");
        frame->velocity = Vec3SGrid::create(openvdb::Vec3s(0.0f));
        frame->velocity->setTransform(frame->surface->transform().copy());
        frame->velocity->setName("v");
        frame->velocity->setGridClass(openvdb::GRID_UNKNOWN);
        frame->velocity->setVectorType(openvdb::VEC_CONTRAVARIANT_RELATIVE);
        *out = frame.release();
        return PVDB_OK;
    });
}

void pvdb_frame_free(PvdbFrame* frame) { delete frame; }

// Adds a level set to the frame (CSG union) and consumes it; `velocities` (3 floats a
// particle, the particles the level set was made from) fill the velocity grid over
// the rasterized band.
int pvdb_frame_add(PvdbFrame* frame, PvdbLevelSet* level_set, const float* velocities,
                   size_t count, char* err, size_t err_len) {
    std::unique_ptr<PvdbLevelSet> owned(level_set);
    return guarded(err, err_len, [&]() -> int {
        if (owned->grid->transform() != frame->surface->transform()) {
            set_error(err, err_len, "the level set's voxel size differs from the frame's");
            return PVDB_INVALID_ARGUMENT;
        }
        if (owned->closest) {
            auto velocity = frame->velocity->getAccessor();
            for (auto it = owned->closest->cbeginValueOn(); it; ++it) {
                const size_t i = *it;
                if (i >= count) {
                    set_error(err, err_len, "a voxel refers to a particle past the end");
                    return PVDB_INVALID_ARGUMENT;
                }
                velocity.setValue(it.getCoord(),
                                  openvdb::Vec3s(velocities[3 * i], velocities[3 * i + 1],
                                                 velocities[3 * i + 2]));
            }
        }
        openvdb::tools::csgUnion(frame->surface->tree(), owned->grid->tree(), true);
        return PVDB_OK;
    });
}

size_t pvdb_frame_active_voxels(const PvdbFrame* frame) {
    return frame->surface->activeVoxelCount();
}

int pvdb_frame_write(const PvdbFrame* frame, const char* path, char* err, size_t err_len) {
    return guarded(err, err_len, [&]() -> int {
        openvdb::GridPtrVec grids;
        grids.push_back(frame->surface);
        grids.push_back(frame->velocity);
        openvdb::io::File file(path);
        file.write(grids);
        file.close();
        return PVDB_OK;
    });
}

}  // extern "C"
