// make_vdb_cloud: writes small OpenVDB files, since none can be downloaded here (lightgraph
// issue 25). Built by meson when OpenVDB is found (plugins/scene_tools/meson.build), which
// also runs it: build/plugins/scene_tools/cloud.vdb for the examples, and the test fixtures.
//
//   make_vdb_cloud cloud OUT.vdb [--res N] [--voxel S] [--center X,Y,Z] [--seed K]
//                    [--samples TXT]
//       An fBm-eroded sphere (a cumulus-like puff): float grid "density" of N^3 voxels
//       (default 64), values in [0, 1], voxel size S world units (default 0.04), its centre
//       at X,Y,Z (default 0,0,0), noise seed K (default 1). Only voxels > 0 are active.
//       --samples: 64 lines "x y z value", OpenVDB's own trilinear sample at world points
//       in and around the grid (write_samples).
//   make_vdb_cloud fixtures DIR
//       The files tests/plugins/scene_tools reads (each described at its writer below).
//
// Exit status: 0 written, 1 failure while writing, 2 bad usage.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

#include "lightgraph/medium.h"
#include "lightgraph/vecmath.h"

using openvdb::Coord;
using openvdb::FloatGrid;

namespace
{

int write_grids(const std::string &path, const openvdb::GridPtrVec &grids)
{
    std::ostringstream os(std::ios_base::binary);
    openvdb::io::Stream(os).write(grids);
    std::ofstream f(path, std::ios_base::binary | std::ios_base::trunc);
    f << os.str();
    f.close();
    if (!f) {
        fprintf(stderr, "make_vdb_cloud: cannot write '%s'\n", path.c_str());
        return 1;
    }
    return 0;
}

int write_bytes(const std::string &path, const std::string &bytes)
{
    std::ofstream f(path, std::ios_base::binary | std::ios_base::trunc);
    f << bytes;
    f.close();
    if (!f) {
        fprintf(stderr, "make_vdb_cloud: cannot write '%s'\n", path.c_str());
        return 1;
    }
    return 0;
}

// Writes "x y z value" lines: for each index point q (fractional allowed), its world position
// by the grid's own transform and OpenVDB's trilinear sample there (tools::BoxSampler, the
// background outside the active voxels): the ground truth the tests compare the medium
// node's field with.
int write_samples(const std::string &path, const FloatGrid &g, const openvdb::Vec3d *q, size_t n)
{
    FILE *f = fopen(path.c_str(), "w");
    if (!f) {
        fprintf(stderr, "make_vdb_cloud: cannot write '%s'\n", path.c_str());
        return 1;
    }
    for (size_t i = 0; i < n; i++) {
        openvdb::Vec3d w = g.transform().indexToWorld(q[i]);
        double v = openvdb::tools::BoxSampler::sample(g.tree(), q[i]);
        fprintf(f, "%.9g %.9g %.9g %.9g\n", w[0], w[1], w[2], v);
    }
    return fclose(f) == 0 ? 0 : 1;
}

FloatGrid::Ptr float_grid(const char *name, double voxel)
{
    FloatGrid::Ptr g = FloatGrid::create(0.0f);
    g->setName(name);
    g->setGridClass(openvdb::GRID_FOG_VOLUME);
    g->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
    return g;
}

int cloud(const char *out, int res, double voxel, const double centre[3], uint32_t seed,
          const char *samples)
{
    FloatGrid::Ptr g = float_grid("density", voxel);
    // index (res - 1) / 2 at the centre
    double half = 0.5 * (res - 1);
    g->transform().postTranslate(openvdb::Vec3d(centre[0] - voxel * half, centre[1] - voxel * half,
                                                centre[2] - voxel * half));
    lg_density_fbm f = {};
    f.octaves = 5;
    f.seed = seed;
    f.frequency = 3.0f;
    f.lacunarity = 2.0f;
    f.gain = 0.5f;
    auto acc = g->getAccessor();
    for (int k = 0; k < res; k++)
        for (int j = 0; j < res; j++)
            for (int i = 0; i < res; i++) {
                // p in [-1, 1]^3 over the grid; a sphere of radius 0.7 eroded by the noise,
                // flattened below (a cloud's base)
                double p[3] = { (i - half) / half, (j - half) / half, (k - half) / half };
                double q[3] = { p[0], p[1] < 0 ? p[1] * 1.6 : p[1], p[2] };
                double r = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
                double d = (0.7 - r) * 4.0 + 1.2 * lg_fbm3(&f, p);
                float v = (float)(d <= 0.0 ? 0.0 : d >= 1.0 ? 1.0 : d);
                if (v > 0.0f)
                    acc.setValue(Coord(i, j, k), v);
            }
    openvdb::GridPtrVec grids{ g };
    int rc = write_grids(out, grids);
    if (samples && !rc) {
        // 64 index points: voxel centres and points between them, spread over the grid
        openvdb::Vec3d q[64];
        uint64_t h = 12345;
        for (int i = 0; i < 64; i++) {
            double c[3];
            for (int k = 0; k < 3; k++) {
                h = h * 6364136223846793005ull + 1442695040888963407ull;
                c[k] = (double)(h >> 40) / (double)(1 << 24) * (res + 1) - 1.0;
                if (i % 2 == 0)
                    c[k] = std::floor(c[k] + 0.5);
            }
            q[i] = openvdb::Vec3d(c[0], c[1], c[2]);
        }
        rc = write_samples(samples, *g, q, 64);
    }
    return rc;
}

int fixtures(const std::string &dir)
{
    int rc = 0;
    // one_voxel.vdb: a vec3 grid "velocity" first, then float grid "density" holding one
    // voxel, [3, -2, 5] = 2, voxel size 0.5 and translation (1, 2, 3) (its centre at world
    // (2.5, 1, 5.5)), then float grid "other": voxel [0, 0, 0] = 7, voxel size 1
    {
        openvdb::Vec3SGrid::Ptr v = openvdb::Vec3SGrid::create();
        v->setName("velocity");
        v->getAccessor().setValue(Coord(0, 0, 0), openvdb::Vec3s(1, 0, 0));
        FloatGrid::Ptr d = float_grid("density", 0.5);
        d->transform().postTranslate(openvdb::Vec3d(1, 2, 3));
        d->getAccessor().setValue(Coord(3, -2, 5), 2.0f);
        FloatGrid::Ptr o = float_grid("other", 1.0);
        o->getAccessor().setValue(Coord(0, 0, 0), 7.0f);
        openvdb::GridPtrVec grids{ v, d, o };
        rc |= write_grids(dir + "/one_voxel.vdb", grids);
        const openvdb::Vec3d q[] = { { 3, -2, 5 },      { 3.5, -2, 5 },     { 3.75, -1.5, 5 },
                                     { 2.25, -2, 5.5 }, { 3.4, -2.3, 4.8 }, { 4.5, -2, 5 } };
        rc |= write_samples(dir + "/one_voxel.txt", *d, q, sizeof q / sizeof q[0]);
        // truncated.vdb: its first half; garbage.vdb: text
        std::ostringstream os(std::ios_base::binary);
        openvdb::io::Stream(os).write(grids);
        std::string all = os.str();
        rc |= write_bytes(dir + "/truncated.vdb", all.substr(0, all.size() / 2));
        rc |= write_bytes(dir + "/garbage.vdb", "this is not a VDB file\n");
    }
    // cloud16.vdb, cloud16.txt: a 16^3 cloud (voxel 0.1, centred at (0, 1, 0)) and 64
    // samples of it
    {
        const double c[3] = { 0, 1, 0 };
        rc |= cloud((dir + "/cloud16.vdb").c_str(), 16, 0.1, c, 3, (dir + "/cloud16.txt").c_str());
    }
    // rotated.vdb: "density" voxels [0, 0, 0] = 1 and [1, 0, 0] = 3, scaled (0.5, 1, 2),
    // rotated 90 degrees about +Y, translated (10, 0, 0): index (i, j, k) is at world
    // (10 + 2 k, j, -0.5 i)
    {
        FloatGrid::Ptr d = float_grid("density", 1.0);
        openvdb::math::Transform::Ptr xf = openvdb::math::Transform::createLinearTransform(1.0);
        xf->preScale(openvdb::Vec3d(0.5, 1.0, 2.0));
        xf->postRotate(LG_HALF_PI, openvdb::math::Y_AXIS);
        xf->postTranslate(openvdb::Vec3d(10, 0, 0));
        d->setTransform(xf);
        d->getAccessor().setValue(Coord(0, 0, 0), 1.0f);
        d->getAccessor().setValue(Coord(1, 0, 0), 3.0f);
        openvdb::GridPtrVec grids{ d };
        rc |= write_grids(dir + "/rotated.vdb", grids);
        const openvdb::Vec3d q[] = { { 0, 0, 0 },        { 1, 0, 0 },   { 0.5, 0, 0 },
                                     { 0.5, 0.5, 0.25 }, { 1.5, 0, 0 }, { -0.5, 0.2, -0.1 } };
        rc |= write_samples(dir + "/rotated.txt", *d, q, sizeof q / sizeof q[0]);
    }
    // negative.vdb: 2 x 2 x 2 voxels of 1, voxel [1, 0, 1] = -1
    // nan.vdb: the same with voxel [0, 1, 0] = NaN
    for (int bad = 0; bad < 2; bad++) {
        FloatGrid::Ptr d = float_grid("density", 1.0);
        auto acc = d->getAccessor();
        for (int k = 0; k < 2; k++)
            for (int j = 0; j < 2; j++)
                for (int i = 0; i < 2; i++)
                    acc.setValue(Coord(i, j, k), 1.0f);
        if (bad == 0)
            acc.setValue(Coord(1, 0, 1), -1.0f);
        else
            acc.setValue(Coord(0, 1, 0), std::numeric_limits<float>::quiet_NaN());
        openvdb::GridPtrVec grids{ d };
        rc |= write_grids(dir + (bad == 0 ? "/negative.vdb" : "/nan.vdb"), grids);
    }
    // vec3.vdb: only a vec3 grid "velocity"
    {
        openvdb::Vec3SGrid::Ptr v = openvdb::Vec3SGrid::create();
        v->setName("velocity");
        v->getAccessor().setValue(Coord(0, 0, 0), openvdb::Vec3s(1, 0, 0));
        openvdb::GridPtrVec grids{ v };
        rc |= write_grids(dir + "/vec3.vdb", grids);
    }
    // levelset.vdb: a float grid of class level set; empty.vdb: a float grid, no voxel;
    // huge.vdb: voxels [0, 0, 0] and [1023, 1023, 1023] (2^30 voxels made dense);
    // frustum.vdb: one voxel under a frustum transform
    {
        FloatGrid::Ptr l = float_grid("surface", 1.0);
        l->setGridClass(openvdb::GRID_LEVEL_SET);
        l->getAccessor().setValue(Coord(0, 0, 0), 0.5f);
        openvdb::GridPtrVec a{ l };
        rc |= write_grids(dir + "/levelset.vdb", a);
        FloatGrid::Ptr e = float_grid("density", 1.0);
        openvdb::GridPtrVec b{ e };
        rc |= write_grids(dir + "/empty.vdb", b);
        FloatGrid::Ptr h = float_grid("density", 1.0);
        h->getAccessor().setValue(Coord(0, 0, 0), 1.0f);
        h->getAccessor().setValue(Coord(1023, 1023, 1023), 1.0f);
        openvdb::GridPtrVec c{ h };
        rc |= write_grids(dir + "/huge.vdb", c);
        FloatGrid::Ptr f = float_grid("density", 1.0);
        f->setTransform(
            openvdb::math::Transform::createFrustumTransform(openvdb::BBoxd(openvdb::Vec3d(0, 0, 0),
                                                                            openvdb::Vec3d(8, 8,
                                                                                           8)),
                                                             0.5, 4.0, 1.0));
        f->getAccessor().setValue(Coord(1, 1, 1), 1.0f);
        openvdb::GridPtrVec d{ f };
        rc |= write_grids(dir + "/frustum.vdb", d);
    }
    return rc;
}

int usage()
{
    fprintf(stderr, "usage: make_vdb_cloud cloud OUT.vdb [--res N] [--voxel S] [--center X,Y,Z] "
                    "[--seed K] [--samples TXT]\n       make_vdb_cloud fixtures DIR\n");
    return 2;
}

} // namespace

int main(int argc, char **argv)
{
    if (argc < 3)
        return usage();
    try {
        openvdb::initialize();
        if (strcmp(argv[1], "fixtures") == 0 && argc == 3)
            return fixtures(argv[2]);
        if (strcmp(argv[1], "cloud") != 0)
            return usage();
        int res = 64;
        double voxel = 0.04, centre[3] = { 0, 0, 0 };
        unsigned long seed = 1;
        const char *samples = nullptr;
        for (int i = 3; i < argc; i++) {
            const char *v = i + 1 < argc ? argv[i + 1] : nullptr;
            char *end = nullptr;
            if (!v)
                return usage();
            if (strcmp(argv[i], "--res") == 0) {
                long r = strtol(v, &end, 10);
                if (*end || r < 2 || r > 512) {
                    fprintf(stderr, "make_vdb_cloud: --res %s: want an integer in 2 .. 512\n", v);
                    return 2;
                }
                res = (int)r;
            } else if (strcmp(argv[i], "--voxel") == 0) {
                voxel = strtod(v, &end);
                if (*end || !(voxel > 0.0) || !std::isfinite(voxel)) {
                    fprintf(stderr, "make_vdb_cloud: --voxel %s: want a size > 0\n", v);
                    return 2;
                }
            } else if (strcmp(argv[i], "--center") == 0) {
                if (sscanf(v, "%lf,%lf,%lf", &centre[0], &centre[1], &centre[2]) != 3 ||
                    !std::isfinite(centre[0] + centre[1] + centre[2])) {
                    fprintf(stderr, "make_vdb_cloud: --center %s: want X,Y,Z\n", v);
                    return 2;
                }
            } else if (strcmp(argv[i], "--seed") == 0) {
                seed = strtoul(v, &end, 10);
                if (*end || seed > 0xffffffffUL) {
                    fprintf(stderr, "make_vdb_cloud: --seed %s: want an integer >= 0\n", v);
                    return 2;
                }
            } else if (strcmp(argv[i], "--samples") == 0) {
                samples = v;
            } else {
                return usage();
            }
            i++;
        }
        return cloud(argv[2], res, voxel, centre, (uint32_t)seed, samples);
    } catch (const std::exception &e) {
        fprintf(stderr, "make_vdb_cloud: %s\n", e.what());
        return 1;
    }
}
