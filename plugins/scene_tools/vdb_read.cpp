// vdb_read.cpp: the C++ shim between the `medium` node (C) and OpenVDB (vdb_read.h). The
// only C++ of the plugin: it parses bytes the node has already read, and turns every
// exception into an error message, since none may cross into C.
#include "vdb_read.h"

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <istream>
#include <streambuf>
#include <string>

#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>

namespace
{

// A read-only stream buffer over the caller's bytes (no copy), seekable because OpenVDB's
// reader may move within the stream.
struct MemBuf : std::streambuf {
    MemBuf(const char *b, size_t n)
    {
        char *p = const_cast<char *>(b);
        setg(p, p, p + n);
    }
    pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode) override
    {
        off_type base = dir == std::ios_base::beg   ? 0
                        : dir == std::ios_base::cur ? gptr() - eback()
                                                    : egptr() - eback();
        off_type to = base + off;
        if (to < 0 || to > egptr() - eback())
            return pos_type(off_type(-1));
        setg(eback(), eback() + to, egptr());
        return pos_type(to);
    }
    pos_type seekpos(pos_type pos, std::ios_base::openmode m) override
    {
        return seekoff(off_type(pos), std::ios_base::beg, m);
    }
};

void say(char *err, size_t errlen, const char *fmt, ...)
{
    if (!err || !errlen)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
}

// "'density' (float), 'v' (vec3s)": the grids of a file, for messages.
std::string grid_list(const openvdb::GridPtrVec &grids)
{
    std::string s;
    for (const auto &g : grids) {
        if (!g)
            continue;
        if (!s.empty())
            s += ", ";
        s += "'" + g->getName() + "' (" + g->valueType() + ")";
    }
    return s.empty() ? std::string("none") : s;
}

int read_grid(const void *bytes, size_t len, const char *want, uint64_t max_voxels,
              st_vdb_grid *out, char *err, size_t errlen)
{
    openvdb::initialize(); // registers the grid types; idempotent
    MemBuf buf(static_cast<const char *>(bytes), len);
    std::istream is(&buf);
    // OpenVDB does not check its reads: past the end of a truncated file it would go on
    // with sizes it never read (uninitialised: a huge allocation one run, garbage the next).
    // A short read throws instead, and becomes "not a readable VDB file".
    is.exceptions(std::ios_base::failbit | std::ios_base::badbit);
    openvdb::io::Stream stream(is, false); // reads the header and every grid now
    openvdb::GridPtrVecPtr grids = stream.getGrids();
    if (!grids || grids->empty()) {
        say(err, errlen, "it holds no grid");
        return -1;
    }
    openvdb::GridBase::Ptr base;
    for (const auto &g : *grids) {
        if (!g)
            continue;
        if (want && *want ? g->getName() == want : g->isType<openvdb::FloatGrid>()) {
            base = g;
            break;
        }
    }
    if (!base) {
        if (want && *want)
            say(err, errlen, "it has no grid named '%s' (its grids: %s)", want,
                grid_list(*grids).c_str());
        else
            say(err, errlen, "it has no float grid (its grids: %s); a density needs one",
                grid_list(*grids).c_str());
        return -1;
    }
    const std::string name = base->getName();
    if (!base->isType<openvdb::FloatGrid>()) {
        say(err, errlen, "grid '%s' holds %s values, not float: a density needs a float grid",
            name.c_str(), base->valueType().c_str());
        return -1;
    }
    openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    if (grid->getGridClass() == openvdb::GRID_LEVEL_SET) {
        say(err, errlen,
            "grid '%s' is a level set (signed distances, not densities): convert it to a fog "
            "volume first (OpenVDB's sdfToFogVolume)",
            name.c_str());
        return -1;
    }
    float bg = grid->background();
    if (!std::isfinite(bg) || bg < 0.0f) {
        say(err, errlen, "grid '%s': its background value %g is %s", name.c_str(), (double)bg,
            std::isfinite(bg) ? "negative: a density is >= 0" : "not finite");
        return -1;
    }
    openvdb::CoordBBox bb = grid->evalActiveVoxelBoundingBox();
    if (bb.empty()) {
        say(err, errlen, "grid '%s' has no active voxel", name.c_str());
        return -1;
    }
    int64_t dim[3];
    for (int c = 0; c < 3; c++)
        dim[c] = (int64_t)bb.max()[c] - (int64_t)bb.min()[c] + 1;
    // in floating point: three sizes up to 2^32 each overflow 64 bits
    double count = (double)dim[0] * (double)dim[1] * (double)dim[2];
    if (count > (double)max_voxels) {
        say(err, errlen,
            "grid '%s': its active voxels span %lld x %lld x %lld = %.3g voxels made dense, over "
            "the limit of %llu",
            name.c_str(), (long long)dim[0], (long long)dim[1], (long long)dim[2], count,
            (unsigned long long)max_voxels);
        return -1;
    }
    const openvdb::math::Transform &xf = grid->transform();
    if (!xf.isLinear()) {
        say(err, errlen,
            "grid '%s': its transform (%s) is not affine; only linear (affine) transforms are "
            "supported",
            name.c_str(), xf.mapType().c_str());
        return -1;
    }
    openvdb::math::Mat4d m = xf.baseMap()->getAffineMap()->getMat4();
    // OpenVDB's matrices act on row vectors (translation in row 3): their row-major storage
    // is the column-major storage of the column-vector matrix lightgraph uses
    const double *mp = m.asPointer();
    double a[16];
    for (int k = 0; k < 16; k++)
        a[k] = mp[k];
    double det = a[0] * (a[5] * a[10] - a[9] * a[6]) - a[4] * (a[1] * a[10] - a[9] * a[2]) +
                 a[8] * (a[1] * a[6] - a[5] * a[2]);
    bool finite = true;
    for (int k = 0; k < 16; k++)
        finite = finite && std::isfinite(a[k]);
    if (!finite || !(std::fabs(det) > 1e-300)) {
        say(err, errlen, "grid '%s': its transform is %s", name.c_str(),
            finite ? "singular (a voxel of zero size)" : "not finite");
        return -1;
    }

    size_t n = (size_t)dim[0] * (size_t)dim[1] * (size_t)dim[2];
    float *values = static_cast<float *>(malloc(n * sizeof(float)));
    if (!values) {
        say(err, errlen, "out of memory for %zu voxels of grid '%s'", n, name.c_str());
        return -1;
    }
    float vmax = 0.0f;
    auto acc = grid->getConstAccessor();
    size_t idx = 0;
    openvdb::Coord c;
    for (int64_t z = 0; z < dim[2]; z++)
        for (int64_t y = 0; y < dim[1]; y++)
            for (int64_t x = 0; x < dim[0]; x++, idx++) {
                c.reset((int32_t)(bb.min()[0] + x), (int32_t)(bb.min()[1] + y),
                        (int32_t)(bb.min()[2] + z));
                float v = acc.getValue(c);
                if (!std::isfinite(v) || v < 0.0f) {
                    openvdb::Vec3d w = xf.indexToWorld(c);
                    say(err, errlen,
                        "grid '%s': voxel [%d, %d, %d] (world [%g, %g, %g]) holds %g: a density "
                        "must be finite and >= 0",
                        name.c_str(), c[0], c[1], c[2], w[0], w[1], w[2], (double)v);
                    free(values);
                    return -1;
                }
                values[idx] = v;
                vmax = v > vmax ? v : vmax;
            }
    memset(out, 0, sizeof *out);
    out->nx = (uint32_t)dim[0];
    out->ny = (uint32_t)dim[1];
    out->nz = (uint32_t)dim[2];
    out->values = values;
    out->max_value = vmax;
    for (int k = 0; k < 3; k++)
        out->bbox_min[k] = bb.min()[k];
    // dense index -> world: A translate(bbox_min)
    for (int k = 0; k < 16; k++)
        out->index_to_world[k] = a[k];
    for (int r = 0; r < 3; r++)
        out->index_to_world[12 + r] = a[12 + r] + a[r] * bb.min()[0] + a[4 + r] * bb.min()[1] +
                                      a[8 + r] * bb.min()[2];
    out->background = bg;
    snprintf(out->name, sizeof out->name, "%s", name.c_str());
    return 0;
}

} // namespace

extern "C" int st_vdb_read(const void *bytes, size_t len, const char *grid, uint64_t max_voxels,
                           st_vdb_grid *out, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    if (err && errlen)
        err[0] = 0;
    try {
        return read_grid(bytes, len, grid, max_voxels, out, err, errlen);
    } catch (const std::ios_base::failure &) {
        say(err, errlen, "not a readable VDB file: it ends before its grids do (truncated?)");
    } catch (const std::bad_alloc &) {
        say(err, errlen, "out of memory while reading it (a corrupt size field?)");
    } catch (const std::exception &e) {
        say(err, errlen, "not a readable VDB file: %s", e.what());
    } catch (...) {
        say(err, errlen, "not a readable VDB file (an unknown error in OpenVDB)");
    }
    free(out->values);
    memset(out, 0, sizeof *out);
    return -1;
}
