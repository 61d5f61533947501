/*
 * The C++ shim: what OpenEXR 3.1's C API cannot do, through its C++ API.
 *   - reading DWAA/DWAB (the C API answers "not yet implemented"), luminance-chroma (RY,
 *     BY) and subsampled files (RgbaInputFile converts those to RGB);
 *   - writing DWAA/DWAB;
 *   - B44/B44A files with float or uint channels, both ways (3.1.5's C core and C++
 *     library disagree on those; the C++ library is the format's reference).
 * Nothing else in lightgraph is C++. Every entry point catches all exceptions and turns
 * them into an error message: no exception crosses into C.
 */
#include <ImathBox.h>
#include <ImfChannelList.h>
#include <ImfCompression.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfRgbaFile.h>
#include <ImfStdIO.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <new>
#include <stdexcept>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

#include "image_priv.h"

namespace
{

const char *compression_name(Imf::Compression c)
{
    static const char *const names[] = { "none",  "rle", "zips", "zip",  "piz",
                                         "pxr24", "b44", "b44a", "dwaa", "dwab" };
    int i = static_cast<int>(c);
    return i >= 0 && i < static_cast<int>(sizeof names / sizeof *names) ? names[i] : "unknown";
}

// An OStream on the file descriptor image.c opened for the atomic write.
class FdOStream : public Imf::OStream
{
  public:
    FdOStream(int fd, const char *name) : Imf::OStream(name), fd_(fd), pos_(0) {}
    void write(const char c[], int n) override
    {
        size_t done = 0;
        while (done < static_cast<size_t>(n)) {
            ssize_t k = pwrite(fd_, c + done, static_cast<size_t>(n) - done,
                               static_cast<off_t>(pos_ + done));
            if (k < 0 && errno == EINTR)
                continue;
            if (k <= 0)
                throw std::runtime_error(std::string("write error: ") +
                                         std::strerror(k < 0 ? errno : ENOSPC));
            done += static_cast<size_t>(k);
        }
        pos_ += done;
    }
    uint64_t tellp() override { return pos_; }
    void seekp(uint64_t pos) override { pos_ = pos; }

  private:
    int fd_;
    uint64_t pos_;
};

// An IStream on the descriptor lg_image_read opened and checked: the C++ library never opens
// the path by name, and never reads past the size found at open.
class FdIStream : public Imf::IStream
{
  public:
    FdIStream(int fd, uint64_t size, const char *name)
        : Imf::IStream(name), fd_(fd), size_(size), pos_(0)
    {
    }
    bool read(char c[], int n) override
    {
        if (n < 0 || pos_ > size_ || static_cast<uint64_t>(n) > size_ - pos_)
            throw std::runtime_error("file truncated (unexpected end of file)");
        size_t done = 0;
        while (done < static_cast<size_t>(n)) {
            ssize_t k = pread(fd_, c + done, static_cast<size_t>(n) - done,
                              static_cast<off_t>(pos_ + done));
            if (k < 0 && errno == EINTR)
                continue;
            if (k < 0)
                throw std::runtime_error(std::string("read error: ") + std::strerror(errno));
            if (k == 0)
                throw std::runtime_error("file truncated (unexpected end of file)");
            done += static_cast<size_t>(k);
        }
        pos_ += done;
        return pos_ < size_;
    }
    uint64_t tellg() override { return pos_; }
    void seekg(uint64_t pos) override { pos_ = pos; }
    void clear() override {}

  private:
    int fd_;
    uint64_t size_, pos_;
};

int read_rgba_file(int fd, uint64_t size, const char *path, const Imath::Box2i &dw, lg_image *img,
                   lg_image_read_info *info)
{
    FdIStream is(fd, size, path);
    Imf::RgbaInputFile file(is);
    size_t w = static_cast<size_t>(static_cast<int64_t>(dw.max.x) - dw.min.x + 1);
    size_t h = static_cast<size_t>(static_cast<int64_t>(dw.max.y) - dw.min.y + 1);
    std::vector<Imf::Rgba> px(w * h);
    // The base pointer addresses pixel (0,0) of the file's coordinate system, which may lie
    // outside the buffer: compute it as an integer to stay clear of pointer-overflow rules.
    intptr_t off = (static_cast<intptr_t>(dw.min.x) +
                    static_cast<intptr_t>(dw.min.y) * static_cast<intptr_t>(w)) *
                   static_cast<intptr_t>(sizeof(Imf::Rgba));
    Imf::Rgba *base = reinterpret_cast<Imf::Rgba *>(reinterpret_cast<intptr_t>(px.data()) - off);
    file.setFrameBuffer(base, 1, w);
    file.readPixels(dw.min.y, dw.max.y);

    if (lg_image_alloc(img, static_cast<uint32_t>(w), static_cast<uint32_t>(h)) != LG_OK)
        throw std::bad_alloc();
    float *d = img->pixels;
    for (size_t i = 0; i < w * h; i++, d += 4) {
        d[0] = px[i].r;
        d[1] = px[i].g;
        d[2] = px[i].b;
        d[3] = px[i].a;
    }
    Imf::RgbaChannels ch = file.channels();
    bool color = (ch & (Imf::WRITE_R | Imf::WRITE_G | Imf::WRITE_B | Imf::WRITE_C)) != 0;
    info->channels = (color ? 3u : 1u) + ((ch & Imf::WRITE_A) ? 1u : 0u);
    info->bits = 16;
    return LG_OK;
}

// OpenEXR's C++ reader allocates an unknown attribute's declared size before reading it,
// and reads known types by their own layout, not by the declared size: a box2i always takes
// 16 bytes, a chlist runs to its empty name, a preview takes 8 + 4 w h. A header whose
// declared sizes disagree with those layouts is parsed one way by the C API (by size) and
// another way by the C++ library, which then takes bytes of a value for the next attribute's
// name, type and size: a 1 KiB file made it allocate 1.6 GB (both found by `make fuzz`).
// The headers are walked here first, from the open descriptor (no second open by name),
// and refused when an attribute declares more bytes than the file has left or a size its
// type cannot have; then both libraries see the same attributes. Returns true when the
// header is refused, with the reason in why.

// A bounded reader over the descriptor, from offset 0 to size.
struct HeadReader {
    int fd;
    long long size, at;
    unsigned char buf[4096];
    long long buf_at;
    int buf_n;
    int getc()
    {
        if (at >= size)
            return -1;
        if (at < buf_at || at >= buf_at + buf_n) {
            ssize_t r = pread(fd, buf, sizeof buf, at);
            if (r <= 0)
                return -1;
            buf_at = at;
            buf_n = static_cast<int>(r);
        }
        return buf[at++ - buf_at];
    }
    bool read(unsigned char *d, int n)
    {
        for (int i = 0; i < n; i++) {
            int c = getc();
            if (c < 0)
                return false;
            d[i] = static_cast<unsigned char>(c);
        }
        return true;
    }
};

static int32_t le32(const unsigned char *b)
{
    return static_cast<int32_t>(static_cast<uint32_t>(b[0]) | (static_cast<uint32_t>(b[1]) << 8) |
                                (static_cast<uint32_t>(b[2]) << 16) |
                                (static_cast<uint32_t>(b[3]) << 24));
}

// The size a known type always takes, or -1 for types read by their declared size (string,
// floatvector, opaque) or checked apart (chlist, preview, stringvector).
static long long fixed_size(const char *type)
{
    static const struct {
        const char *name;
        int size;
    } known[] = {
        { "box2i", 16 },      { "box2f", 16 },   { "chromaticities", 32 },
        { "compression", 1 }, { "double", 8 },   { "envmap", 1 },
        { "float", 4 },       { "int", 4 },      { "keycode", 28 },
        { "lineOrder", 1 },   { "m33f", 36 },    { "m33d", 72 },
        { "m44f", 64 },       { "m44d", 128 },   { "rational", 8 },
        { "tiledesc", 9 },    { "timecode", 8 }, { "v2i", 8 },
        { "v2f", 8 },         { "v2d", 16 },     { "v3i", 12 },
        { "v3f", 12 },        { "v3d", 24 },     { "deepImageState", 1 },
    };
    for (const auto &k : known)
        if (std::strcmp(k.name, type) == 0)
            return k.size;
    return -1;
}

// Checks a value of `len` bytes at the reader's position against its type's layout; the
// reader ends after the value either way. False with the reason in why.
static bool value_ok(HeadReader &r, const char *name, const char *type, long long len, char *why,
                     size_t whylen)
{
    const long long end = r.at + len;
    long long want = fixed_size(type);
    bool ok = true;
    if (want >= 0) {
        ok = len == want;
        if (!ok)
            std::snprintf(why, whylen,
                          "header attribute '%.120s' of type %.40s declares %lld bytes, "
                          "not %lld",
                          name, type, len, want);
    } else if (std::strcmp(type, "chlist") == 0) {
        // entries: name (1..255 bytes), NUL, 16 bytes; then an empty name
        for (;;) {
            int c = r.getc(), n = 0;
            while (c > 0 && r.at <= end) {
                n++;
                c = r.getc();
            }
            if (c < 0 || r.at > end || n > 255) {
                ok = false;
                break;
            }
            if (n == 0)
                break;
            r.at += 16;
            if (r.at > end) {
                ok = false;
                break;
            }
        }
        ok = ok && r.at == end;
        if (!ok)
            std::snprintf(why, whylen,
                          "header attribute '%.120s' (chlist) does not fill its %lld "
                          "declared bytes exactly",
                          name, len);
    } else if (std::strcmp(type, "preview") == 0) {
        unsigned char b[8];
        ok = len >= 8 && r.read(b, 8);
        long long w = ok ? static_cast<uint32_t>(le32(b)) : 0;
        long long h = ok ? static_cast<uint32_t>(le32(b + 4)) : 0;
        ok = ok && w <= 65535 && h <= 65535 && 8 + 4 * w * h == len;
        if (!ok)
            std::snprintf(why, whylen,
                          "header attribute '%.120s' (preview) declares %lld bytes, "
                          "not 8 + 4 x its %lld x %lld pixels",
                          name, len, w, h);
    } else if (std::strcmp(type, "stringvector") == 0) {
        // [int length][bytes] until the declared size is used up, exactly
        while (ok && r.at < end) {
            unsigned char b[4];
            ok = end - r.at >= 4 && r.read(b, 4);
            long long n = ok ? le32(b) : -1;
            ok = ok && n >= 0 && n <= end - r.at;
            if (ok)
                r.at += n;
        }
        ok = ok && r.at == end;
        if (!ok)
            std::snprintf(why, whylen,
                          "header attribute '%.120s' (stringvector) holds a string "
                          "longer than its %lld declared bytes",
                          name, len);
    } else if (std::strcmp(type, "floatvector") == 0) {
        ok = len % 4 == 0;
        if (!ok)
            std::snprintf(why, whylen,
                          "header attribute '%.120s' (floatvector) declares %lld "
                          "bytes, not a whole number of floats",
                          name, len);
    }
    r.at = end;
    return ok;
}

bool attribute_over_file(int fd, uint64_t size, char *why, size_t whylen)
{
    HeadReader r{ fd, static_cast<long long>(size), 0, {}, 0, 0 };
    unsigned char v[8];
    if (!r.read(v, 8))
        return false;                          // short: OpenEXR says so
    const bool multipart = (v[5] & 0x10) != 0; // version flag 0x1000: headers until an empty one
    const int max_name = (v[5] & 0x04) ? 255 : 31; // long names (flag 0x400)
    for (;;) {
        int n_attrs = 0;
        for (;;) {
            char name[256], type[256];
            int c = 0, n = 0;
            while (n < 255 && (c = r.getc()) > 0)
                name[n++] = c < 0x20 || c > 0x7e ? '?' : static_cast<char>(c); // for the message
            if (c < 0 || (n == 255 && c != 0))
                return false; // a short file or an overlong name: OpenEXR says which
            if (n == 255)
                (void)r.getc(); // the NUL after a 255-byte name was not read yet
            name[n] = 0;
            if (n == 0) // the empty name ending a header
                break;
            (void)max_name;
            n = 0;
            while (n < 255 && (c = r.getc()) > 0)
                type[n++] = static_cast<char>(c);
            if (c < 0 || n == 255)
                return false;
            type[n] = 0;
            unsigned char b[4];
            if (!r.read(b, 4))
                return false;
            n_attrs++;
            long long len = le32(b);
            if (len < 0 || len > r.size - r.at) {
                std::snprintf(why, whylen,
                              "header attribute '%.120s' declares %lld bytes, more "
                              "than the %lld left in the file",
                              name, len, r.size - r.at);
                return true;
            }
            if (!value_ok(r, name, type, len, why, whylen))
                return true;
        }
        if (!multipart || n_attrs == 0)
            return false;
    }
}

} // namespace

extern "C" int lg_exr_cxx_read(int fd, uint64_t size, const char *path, lg_image *img,
                               lg_image_read_info *info, char *err, size_t errlen)
{
    char why[512];
    if (attribute_over_file(fd, size, why, sizeof why))
        return lg_image_fail(err, errlen, LG_ERR_INVALID, "cannot read '%s': %s", path, why);
    try {
        FdIStream is(fd, size, path);
        Imf::InputFile file(is);
        const Imf::Header &hdr = file.header();
        const Imath::Box2i dw = hdr.dataWindow();
        int64_t w = static_cast<int64_t>(dw.max.x) - dw.min.x + 1;
        int64_t h = static_cast<int64_t>(dw.max.y) - dw.min.y + 1;
        if (w <= 0 || h <= 0 || w > INT32_MAX || h > INT32_MAX)
            return lg_image_fail(err, errlen, LG_ERR_INVALID,
                                 "cannot read '%s': data window %lldx%lld is empty or too wide",
                                 path, static_cast<long long>(w), static_cast<long long>(h));
        // The C path checked this already (it sends files here only after its own checks);
        // again, since this is the size the buffers below are made for. RgbaInputFile
        // needs 8 bytes of half RGBA per pixel besides the result.
        int rc = lg_image_check_size(path, static_cast<uint64_t>(w), static_cast<uint64_t>(h), 8, 0,
                                     err, errlen);
        if (rc != LG_OK)
            return rc;
        std::snprintf(info->compression, sizeof info->compression, "%s",
                      compression_name(hdr.compression()));

        const Imf::ChannelList &cl = hdr.channels();
        bool chroma = cl.findChannel("RY") || cl.findChannel("BY");
        bool subsampled = false, is_float = false;
        for (Imf::ChannelList::ConstIterator it = cl.begin(); it != cl.end(); ++it) {
            const char *n = it.name();
            bool used = !std::strcmp(n, "R") || !std::strcmp(n, "G") || !std::strcmp(n, "B") ||
                        !std::strcmp(n, "A") || !std::strcmp(n, "Y");
            if (!used)
                continue;
            if (it.channel().xSampling != 1 || it.channel().ySampling != 1)
                subsampled = true;
            if (it.channel().type != Imf::HALF)
                is_float = true;
        }
        if (chroma || subsampled)
            return read_rgba_file(fd, size, path, dw, img, info);

        bool has_r = cl.findChannel("R"), has_g = cl.findChannel("G"), has_b = cl.findChannel("B");
        bool has_a = cl.findChannel("A"), has_y = cl.findChannel("Y");
        bool rgb = has_r || has_g || has_b;
        if (!rgb && !has_y) {
            std::string names;
            for (Imf::ChannelList::ConstIterator it = cl.begin(); it != cl.end(); ++it)
                names += (names.empty() ? "" : ", ") + std::string(it.name());
            return lg_image_fail(err, errlen, LG_ERR_UNSUPPORTED,
                                 "cannot read '%s': no R, G, B or Y channel (channels: %s)", path,
                                 names.empty() ? "none" : names.c_str());
        }
        if (lg_image_alloc(img, static_cast<uint32_t>(w), static_cast<uint32_t>(h)) != LG_OK)
            return lg_image_fail(err, errlen, LG_ERR_NOMEM,
                                 "cannot read '%s': out of memory for %lldx%lld", path,
                                 static_cast<long long>(w), static_cast<long long>(h));

        // Straight into the interleaved RGBA float image: channels the file lacks are
        // filled (0 for colour, 1 for alpha).
        const size_t xs = 4 * sizeof(float), ys = xs * static_cast<size_t>(w);
        float *p = img->pixels;
        Imf::FrameBuffer fb;
        if (rgb) {
            fb.insert("R", Imf::Slice::Make(Imf::FLOAT, p + 0, dw, xs, ys, 1, 1, 0.0));
            fb.insert("G", Imf::Slice::Make(Imf::FLOAT, p + 1, dw, xs, ys, 1, 1, 0.0));
            fb.insert("B", Imf::Slice::Make(Imf::FLOAT, p + 2, dw, xs, ys, 1, 1, 0.0));
        } else {
            fb.insert("Y", Imf::Slice::Make(Imf::FLOAT, p + 0, dw, xs, ys, 1, 1, 0.0));
        }
        fb.insert("A", Imf::Slice::Make(Imf::FLOAT, p + 3, dw, xs, ys, 1, 1, 1.0));
        file.setFrameBuffer(fb);
        file.readPixels(dw.min.y, dw.max.y);
        if (!rgb) {
            for (size_t i = 0, n = static_cast<size_t>(w * h); i < n; i++)
                p[4 * i + 1] = p[4 * i + 2] = p[4 * i];
        }
        info->channels = (rgb ? 3u : 1u) + (has_a ? 1u : 0u);
        info->bits = is_float ? 32 : 16;
        return LG_OK;
    } catch (const std::bad_alloc &) {
        lg_image_free(img);
        return lg_image_fail(err, errlen, LG_ERR_NOMEM, "cannot read '%s': out of memory", path);
    } catch (const std::exception &e) {
        lg_image_free(img);
        return lg_image_fail(err, errlen, LG_ERR_INVALID, "cannot read '%s': %s", path, e.what());
    } catch (...) {
        lg_image_free(img);
        return lg_image_fail(err, errlen, LG_ERR_INVALID, "cannot read '%s': unknown error", path);
    }
}

extern "C" int lg_exr_cxx_write(int fd, const char *path, const lg_image *img, int half,
                                uint32_t channels, int compression, char *err, size_t errlen)
{
    static const Imf::Compression map[] = {
        Imf::ZIP_COMPRESSION,  Imf::NO_COMPRESSION,    Imf::RLE_COMPRESSION, Imf::ZIPS_COMPRESSION,
        Imf::PIZ_COMPRESSION,  Imf::PXR24_COMPRESSION, Imf::B44_COMPRESSION, Imf::B44A_COMPRESSION,
        Imf::DWAA_COMPRESSION, Imf::DWAB_COMPRESSION,
    };
    if (compression < 0 || compression >= static_cast<int>(sizeof map / sizeof *map))
        return lg_image_fail(err, errlen, LG_ERR_INVALID, "cannot write '%s': bad compression %d",
                             path, compression);
    try {
        int w = static_cast<int>(img->width), h = static_cast<int>(img->height);
        Imf::Header header(w, h);
        header.compression() = map[compression];
        Imf::PixelType type = half ? Imf::HALF : Imf::FLOAT;
        static const char *const names[4] = { "R", "G", "B", "A" };
        for (uint32_t c = 0; c < channels; c++)
            header.channels().insert(names[c], Imf::Channel(type));

        // OutputFile converts nothing: a half channel needs a half frame buffer. The
        // conversion is lightgraph's own (round to nearest even, beyond 65504 to Inf), the
        // same as the C API path's.
        std::vector<uint16_t> halves;
        Imf::FrameBuffer fb;
        size_t npx = static_cast<size_t>(img->width) * img->height;
        if (half) {
            halves.resize(npx * 4);
            for (size_t i = 0; i < npx * 4; i++)
                halves[i] = lg_half_from_float(img->pixels[i]);
            const size_t xs = 4 * sizeof(uint16_t), ys = xs * img->width;
            for (uint32_t c = 0; c < channels; c++)
                fb.insert(names[c],
                          Imf::Slice(Imf::HALF, reinterpret_cast<char *>(&halves[c]), xs, ys));
        } else {
            const size_t xs = 4 * sizeof(float), ys = xs * img->width;
            for (uint32_t c = 0; c < channels; c++)
                fb.insert(names[c], Imf::Slice(Imf::FLOAT,
                                               reinterpret_cast<char *>(img->pixels + c), xs, ys));
        }
        FdOStream os(fd, path);
        Imf::OutputFile out(os, header);
        out.setFrameBuffer(fb);
        out.writePixels(h);
        return LG_OK;
    } catch (const std::bad_alloc &) {
        return lg_image_fail(err, errlen, LG_ERR_NOMEM, "cannot write '%s': out of memory", path);
    } catch (const std::exception &e) {
        return lg_image_fail(err, errlen, LG_ERR_IO, "cannot write '%s' (%s compression): %s", path,
                             compression_name(map[compression]), e.what());
    } catch (...) {
        return lg_image_fail(err, errlen, LG_ERR_IO, "cannot write '%s': unknown error", path);
    }
}
