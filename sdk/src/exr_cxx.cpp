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

namespace {

const char *compression_name(Imf::Compression c)
{
    static const char *const names[] = {"none", "rle",   "zips", "zip",  "piz",
                                        "pxr24", "b44", "b44a", "dwaa", "dwab"};
    int i = static_cast<int>(c);
    return i >= 0 && i < static_cast<int>(sizeof names / sizeof *names) ? names[i] : "unknown";
}

// An OStream on the file descriptor image.c opened for the atomic write.
class FdOStream : public Imf::OStream {
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
class FdIStream : public Imf::IStream {
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
    intptr_t off = (static_cast<intptr_t>(dw.min.x) + static_cast<intptr_t>(dw.min.y) *
                                                          static_cast<intptr_t>(w)) *
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

// OpenEXR's C++ reader allocates each header attribute's declared size before reading it:
// a 1 KiB file whose unknown attribute declares 1.6 GB took that much (found by `make
// fuzz`). The headers are walked here first, and an attribute that declares more bytes
// than the file has left is refused with its name. Anything else odd is left for OpenEXR
// to report. Returns true when an attribute is over, with the reason in why.
bool attribute_over_file(const char *path, char *why, size_t whylen)
{
    FILE *f = std::fopen(path, "rb");
    struct stat st;
    if (!f)
        return false;
    unsigned char v[8];
    if (fstat(fileno(f), &st) != 0 || std::fread(v, 1, 8, f) != 8) {
        std::fclose(f);
        return false;
    }
    const long long size = static_cast<long long>(st.st_size);
    const bool multipart = (v[5] & 0x10) != 0; // version flag 0x1000: headers until an empty one
    bool over = false, done = false;
    while (!done && !over) {
        int n_attrs = 0;
        for (;;) {
            char name[256], type[256];
            int c = 0;
            size_t n = 0;
            while (n < sizeof name && (c = std::fgetc(f)) > 0)
                name[n++] = c < 0x20 || c > 0x7e ? '?' : static_cast<char>(c); // for the message
            if (c < 0 || n == sizeof name) {
                done = true; // a short file or an overlong name: OpenEXR says which
                break;
            }
            name[n] = 0;
            if (n == 0) // the empty name ending a header
                break;
            n = 0;
            while (n < sizeof type && (c = std::fgetc(f)) > 0)
                type[n++] = static_cast<char>(c);
            unsigned char b[4];
            if (c < 0 || n == sizeof type || std::fread(b, 1, 4, f) != 4) {
                done = true;
                break;
            }
            n_attrs++;
            int32_t len = static_cast<int32_t>(static_cast<uint32_t>(b[0]) | (b[1] << 8) |
                                               (b[2] << 16) | (static_cast<uint32_t>(b[3]) << 24));
            long long at = std::ftell(f);
            if (len < 0 || at < 0 || len > size - at) {
                std::snprintf(why, whylen, "header attribute '%s' declares %lld bytes, more than "
                              "the %lld left in the file", name, static_cast<long long>(len),
                              at < 0 ? 0 : size - at);
                over = true;
                break;
            }
            if (std::fseek(f, len, SEEK_CUR) != 0) {
                done = true;
                break;
            }
        }
        if (!multipart || n_attrs == 0)
            done = true;
    }
    std::fclose(f);
    return over;
}

} // namespace

extern "C" int lg_exr_cxx_read(int fd, uint64_t size, const char *path, lg_image *img,
                               lg_image_read_info *info, char *err, size_t errlen)
{
    char why[512];
    if (attribute_over_file(path, why, sizeof why))
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
        int rc = lg_image_check_size(path, static_cast<uint64_t>(w), static_cast<uint64_t>(h), 8,
                                     0, err, errlen);
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
        static const char *const names[4] = {"R", "G", "B", "A"};
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
                fb.insert(names[c], Imf::Slice(Imf::HALF, reinterpret_cast<char *>(&halves[c]),
                                               xs, ys));
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
