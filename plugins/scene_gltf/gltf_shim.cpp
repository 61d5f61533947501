// gltf_shim.cpp: the plugin's only C++. tinygltf 2.7.0 parses the file; this file copies
// the model into the plain C structs of gltf_doc.h, decodes Draco primitives with libdraco,
// and turns every failure and exception into a message (see gltf_doc.h).
//
// tinygltf's own Draco path (TINYGLTF_ENABLE_DRACO) is deliberately not compiled in: in
// 2.7.0 it indexes bufferViews and buffers without bounds checks, dereferences a null
// attribute for an unknown Draco attribute id, ignores decode failures (the accessors then
// silently keep pointing at the compressed bytes) and truncates indices to 8 bits for
// UNSIGNED_BYTE index accessors. lg_draco_decode below does the same job with every check,
// after the loader has validated the extension's bufferView (gltf_load.c).
//
// Without its Draco path, tinygltf 2.7.0 refuses a primitive whose "indices" accessor has no
// bufferView, which is how every Draco primitive is written (the indices are in the Draco
// stream). So a file that uses KHR_draco_mesh_compression gets those primitives' "indices"
// removed from its JSON before tinygltf reads it (without_draco_indices); the decoded Draco
// faces are the indices.
//
// tinygltf is also guarded against two crashes found while fuzzing its 2.7.0 sources:
// its GLB reader accepts a BIN chunk whose length runs 8 bytes past the file (the chunk
// header is not counted), and its extras/extensions converter recurses once per JSON
// nesting level. The GLB container and the JSON nesting depth are checked here first.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

#include <draco/compression/decode.h>
#include <draco/core/decoder_buffer.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <climits>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include "gltf_doc.h"
extern "C" {
#include "gltf_load.h" // the limits
}
#include "lightgraph/file.h"

namespace
{

// Deepest JSON nesting accepted (glTF itself needs 6; extras get the rest).
constexpr int kMaxJsonDepth = 64;
// Largest file the loader reads (tinygltf takes sizes as unsigned int).
constexpr size_t kMaxFileSize = size_t(LG_GLTF_MAX_FILE);
static_assert(LG_GLTF_MAX_FILE <= UINT32_MAX, "tinygltf 2.7.0 takes sizes as unsigned int");

void set_err(char *err, size_t size, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
void set_err(char *err, size_t size, const char *fmt, ...)
{
    if (!err || !size)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, size, fmt, ap);
    va_end(ap);
}

// tinygltf's messages end in newlines and may hold several lines: one line, "; "-joined.
std::string one_line(const std::string &s)
{
    std::string out;
    bool pending = false; // a line break seen since the last character
    for (char c : s) {
        if (c == '\n' || c == '\r') {
            pending = !out.empty();
            continue;
        }
        if (pending)
            out += "; ";
        pending = false;
        out += c;
    }
    return out;
}

uint32_t rd32(const uint8_t *p)
{
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

// The GLB container (glTF 2.0 spec, "Binary glTF Layout"): 12-byte header, a JSON chunk,
// an optional BIN chunk, each chunk 8 bytes of header plus its length. Returns "" or why
// not. On success json/json_size is the JSON chunk.
std::string check_glb(const uint8_t *b, size_t size, const uint8_t **json, size_t *json_size)
{
    if (size < 20)
        return "truncated GLB: " + std::to_string(size) +
               " bytes, the header and first chunk header need 20";
    uint32_t version = rd32(b + 4), length = rd32(b + 8);
    if (version != 2)
        return "GLB version " + std::to_string(version) + " (only 2 is glTF 2.0)";
    if (length > size)
        return "truncated GLB: the header says " + std::to_string(length) +
               " bytes, the file has " + std::to_string(size);
    if (length < size)
        size = length; // trailing bytes after the declared length are ignored, as the spec says
    uint64_t json_len = rd32(b + 12);
    if (rd32(b + 16) != 0x4E4F534Au)
        return "the first GLB chunk is not JSON";
    if (json_len == 0 || 20 + json_len > size)
        return "the GLB JSON chunk (" + std::to_string(json_len) +
               " bytes) runs past the end of the file (" + std::to_string(size) + " bytes)";
    uint64_t at = 20 + json_len;
    if (at < size) {
        if (at + 8 > size)
            return "truncated GLB: a chunk header is cut off at byte " + std::to_string(at);
        uint64_t bin_len = rd32(b + at);
        if (rd32(b + at + 4) != 0x004E4942u)
            return "the second GLB chunk is not BIN";
        if (at + 8 + bin_len > size)
            return "the GLB BIN chunk (" + std::to_string(bin_len) + " bytes at byte " +
                   std::to_string(at + 8) + ") runs past the end of the file (" +
                   std::to_string(size) + " bytes)";
    }
    *json = b + 20;
    *json_size = size_t(json_len);
    return "";
}

// Nesting depth of JSON text (brackets outside strings); stops counting at the limit.
int json_depth(const uint8_t *s, size_t n)
{
    int depth = 0, max = 0;
    bool in_string = false;
    for (size_t i = 0; i < n; i++) {
        uint8_t c = s[i];
        if (in_string) {
            if (c == '\\')
                i++;
            else if (c == '"')
                in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > max && (max = depth) > kMaxJsonDepth)
                return max;
        } else if (c == ']' || c == '}') {
            depth--;
        }
    }
    return max;
}

// The JSON with "indices" removed from every primitive that has KHR_draco_mesh_compression,
// or "" when there is none. Throws nlohmann's exceptions on bad JSON.
std::string without_draco_indices(const uint8_t *json, size_t size)
{
    static const char ext[] = "KHR_draco_mesh_compression";
    if (!memmem(json, size, ext, sizeof ext - 1))
        return "";
    nlohmann::json j = nlohmann::json::parse(json, json + size);
    bool changed = false;
    auto meshes = j.find("meshes");
    if (j.is_object() && meshes != j.end() && meshes->is_array())
        for (auto &mesh : *meshes) {
            if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array())
                continue;
            for (auto &p : mesh["primitives"]) {
                if (!p.is_object() || !p.contains("indices"))
                    continue;
                auto e = p.find("extensions");
                if (e != p.end() && e->is_object() && e->contains(ext)) {
                    p.erase("indices");
                    changed = true;
                }
            }
        }
    return changed ? j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) : "";
}

// A GLB with its JSON chunk replaced (padded with spaces to 4 bytes, as the spec says).
std::vector<uint8_t> replace_glb_json(const uint8_t *glb, size_t size, size_t old_json,
                                      const std::string &json)
{
    std::string j = json;
    while (j.size() % 4)
        j += ' ';
    size_t rest_at = 20 + old_json, rest = size > rest_at ? size - rest_at : 0;
    std::vector<uint8_t> out(20 + j.size() + rest);
    memcpy(out.data(), glb, 12);
    uint32_t total = uint32_t(out.size()), jl = uint32_t(j.size()), type = 0x4E4F534Au;
    for (int k = 0; k < 4; k++) {
        out[8 + k] = uint8_t(total >> (8 * k));
        out[12 + k] = uint8_t(jl >> (8 * k));
        out[16 + k] = uint8_t(type >> (8 * k));
    }
    memcpy(out.data() + 20, j.data(), j.size());
    if (rest)
        memcpy(out.data() + 20 + j.size(), glb + rest_at, rest);
    return out;
}

// ---- external files: what the model may read, and from where ------------------------------------
//
// tinygltf never touches the filesystem by itself: its callbacks below answer only for the
// external buffers that scan_refs found and checked, and read them through lightgraph/file.h
// (regular files only, confined to the model's folder with every link resolved, bounded).
// Before tinygltf runs, scan_refs reads the JSON's "buffers" and "images" and refuses, with
// the uri in the message: a uri that is not a relative reference (a scheme such as file: or
// http:, or a data: URI tinygltf would not decode), malformed percent-encoding or a NUL, a
// path that leaves the model's folder (lexically, or once its links are resolved), a buffer
// file that is not a regular file (a FIFO, /dev/zero), a byteLength over kMaxBufferSize or
// external buffers over kMaxExternalTotal in all, and a file shorter than its byteLength.
// None of that reads a byte of the file. Images are never read (the loader ignores
// textures), but are held to the same folder.

// Largest external buffer (a byteLength), and all external buffers of a file together.
constexpr uint64_t kMaxBufferSize = LG_GLTF_MAX_BUFFER;
constexpr uint64_t kMaxExternalTotal = LG_GLTF_MAX_EXTERNAL;

// One external (non-data:) buffer, in file order: tinygltf loads them in that order.
struct ext_buffer {
    size_t index;      // in "buffers"
    std::string uri;   // as the file writes it
    std::string path;  // percent-decoded (RFC 3986), relative to the model's folder
    std::string asked; // the path tinygltf asks for: base + "/" + its own decoding
    uint64_t byte_length;
};

struct fs_context {
    std::string base; // the model's folder (absolute, links resolved), "" when none
    std::vector<ext_buffer> buffers;
    size_t next = 0;   // the buffer tinygltf reads next
    std::string error; // the first refusal, reported instead of tinygltf's message
};

// s for a one-line message: control characters as \xNN, at most 200 bytes.
std::string printable(const std::string &s)
{
    std::string out;
    size_t i = 0;
    for (; i < s.size() && out.size() < 200; i++) {
        unsigned char c = (unsigned char)s[i];
        if (c < 0x20 || c == 0x7f) {
            char hex[8];
            snprintf(hex, sizeof hex, "\\x%02x", c);
            out += hex;
        } else {
            out += char(c);
        }
    }
    return i < s.size() ? out + "..." : out;
}

// "'a%20b.bin' ('a b.bin')", or "'x.bin'" when decoding changes nothing.
std::string quoted_uri(const std::string &uri, const std::string &path)
{
    return uri == path ? "'" + printable(uri) + "'"
                       : "'" + printable(uri) + "' ('" + printable(path) + "')";
}

int hex_digit(char c)
{
    return c >= '0' && c <= '9'   ? c - '0'
           : c >= 'a' && c <= 'f' ? c - 'a' + 10
           : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                  : -1;
}

// Percent-decodes a URI reference (RFC 3986 2.1; glTF 2.0 URIs are RFC 3986 references).
// Unlike tinygltf's decoder, '+' stays '+' (turning it into a space is form encoding), and
// a '%' without two hex digits, or a NUL (encoded or not), is refused rather than guessed.
// Returns "" or why not.
std::string percent_decode(const std::string &uri, std::string *out)
{
    out->clear();
    for (size_t i = 0; i < uri.size(); i++) {
        char c = uri[i];
        if (c == '%') {
            int hi = i + 2 < uri.size() ? hex_digit(uri[i + 1]) : -1;
            int lo = i + 2 < uri.size() ? hex_digit(uri[i + 2]) : -1;
            if (hi < 0 || lo < 0)
                return "malformed percent-encoding at character " + std::to_string(i + 1);
            c = char(hi * 16 + lo);
            i += 2;
        }
        if (c == 0)
            return "it holds a NUL character";
        *out += c;
    }
    return "";
}

// Whether a URI reference starts with a scheme ("file:", "http:", "C:"): RFC 3986 3.1,
// ALPHA *( ALPHA / DIGIT / "+" / "-" / "." ) ":" before any '/'. A relative path whose
// first segment holds a colon must be written "./a:b" (RFC 3986 4.2).
bool has_scheme(const std::string &uri)
{
    if (uri.empty() || !isalpha((unsigned char)uri[0]))
        return false;
    for (size_t i = 1; i < uri.size(); i++) {
        char c = uri[i];
        if (c == ':')
            return true;
        if (!isalnum((unsigned char)c) && c != '+' && c != '-' && c != '.')
            return false;
    }
    return false;
}

// base (absolute, normalised) joined with path and normalised without looking at the
// filesystem ("." and ".." applied, as RFC 3986 5.2.4 does); *escapes when the result is
// not base or below it. Links are the filesystem check's (lg_path_within).
std::string lexical_join(const std::string &base, const std::string &path, bool *escapes)
{
    std::vector<std::string> parts;
    auto add = [&](const std::string &p) {
        size_t at = 0;
        while (at <= p.size()) {
            size_t slash = p.find('/', at);
            if (slash == std::string::npos)
                slash = p.size();
            std::string seg = p.substr(at, slash - at);
            at = slash + 1;
            if (seg == "..") {
                if (!parts.empty())
                    parts.pop_back();
            } else if (!seg.empty() && seg != ".") {
                parts.push_back(seg);
            }
        }
    };
    if (path.empty() || path[0] != '/')
        add(base);
    add(path);
    std::string out;
    for (const auto &p : parts)
        out += "/" + p;
    if (out.empty())
        out = "/";
    *escapes = !(base == "/" || out == base || out.compare(0, base.size() + 1, base + "/") == 0);
    return out;
}

// The reason lightgraph/file.h gave, with its "'PATH' leads to" made "it leads to" (the
// caller already names the uri).
std::string file_reason(const char *why, const std::string &path)
{
    std::string w = why, lead = "'" + path + "' leads to";
    if (w.compare(0, lead.size(), lead) == 0)
        return "it leads to" + w.substr(lead.size());
    return w;
}

// Checks a referenced uri: relative, well encoded, inside the folder (lexically; then, when
// the file exists, with its links resolved). Returns "" or the refusal, naming the uri.
std::string check_uri(const fs_context &ctx, const std::string &what, const std::string &uri,
                      std::string *path, bool must_exist)
{
    std::string why = percent_decode(uri, path);
    if (!why.empty())
        return what + ": cannot read '" + printable(uri) + "': " + why;
    if (has_scheme(uri))
        return what + ": cannot read '" + printable(uri) +
               "': only relative paths inside the model's folder and base64 data: URIs are read";
    if (ctx.base.empty()) {
        if (must_exist)
            return what + ": cannot read " + quoted_uri(uri, *path) +
                   ": the model was loaded from memory, without a folder for external files";
        // no folder: the uri must not climb out of one, wherever the model would be
        bool escapes = false;
        lexical_join("/m", *path, &escapes);
        return escapes ? what + ": cannot read " + quoted_uri(uri, *path) +
                             ": it leaves the model's folder"
                       : "";
    }
    bool escapes = false;
    std::string lexical = lexical_join(ctx.base, *path, &escapes);
    if (escapes)
        return what + ": cannot read " + quoted_uri(uri, *path) + ": it leads to '" +
               printable(lexical) + "', outside '" + ctx.base + "'";
    char err[PATH_MAX + 512];
    if (lg_path_within(ctx.base.c_str(), path->c_str(), err, sizeof err) != 0 &&
        (must_exist || errno == EACCES))
        return what + ": cannot read " + quoted_uri(uri, *path) + ": " + file_reason(err, *path);
    return "";
}

// Opens buffer b (confined, regular, at least byte_length bytes). Returns the descriptor,
// or -1 with the refusal in *why.
int open_buffer(const fs_context &ctx, const ext_buffer &b, std::string *why)
{
    char err[PATH_MAX + 512];
    uint64_t size = 0;
    int fd = lg_file_open_within(ctx.base.c_str(), b.path.c_str(), UINT64_MAX, &size, err,
                                 sizeof err);
    std::string what = "buffer " + std::to_string(b.index) + ": cannot read " +
                       quoted_uri(b.uri, b.path) + ": ";
    if (fd < 0) {
        *why = what + file_reason(err, b.path);
        return -1;
    }
    if (size < b.byte_length) {
        close(fd);
        *why = what + "it has " + std::to_string(size) + " bytes, fewer than its byteLength " +
               std::to_string(b.byte_length);
        return -1;
    }
    return fd;
}

// Reads the JSON's buffers and images and checks every external reference (above). The
// JSON is parsed keeping only those two arrays, and only the head of each data: URI.
std::string scan_refs(const uint8_t *json_text, size_t size, fs_context *ctx)
{
    using nlohmann::json;
    auto keep = [](int depth, json::parse_event_t ev, json &v) {
        if (ev == json::parse_event_t::key && depth == 1)
            return v == "buffers" || v == "images";
        if (ev == json::parse_event_t::value && v.is_string()) {
            const std::string &s = v.get_ref<const std::string &>();
            if (s.size() > 64 && s.compare(0, 5, "data:") == 0)
                v = s.substr(0, 64);
        }
        return true;
    };
    const char *text = reinterpret_cast<const char *>(json_text);
    json j = json::parse(text, text + size, keep);
    if (!j.is_object())
        return ""; // tinygltf says what is wrong
    uint64_t total = 0;
    auto buffers = j.find("buffers");
    if (buffers != j.end() && buffers->is_array())
        for (size_t i = 0; i < buffers->size(); i++) {
            const json &b = (*buffers)[i];
            auto uri = b.is_object() ? b.find("uri") : b.end();
            if (!b.is_object() || uri == b.end() || !uri->is_string() ||
                uri->get_ref<const std::string &>().empty())
                continue; // a GLB's BIN chunk, or an error tinygltf reports
            const std::string &u = uri->get_ref<const std::string &>();
            if (tinygltf::IsDataURI(u))
                continue;
            std::string what = "buffer " + std::to_string(i);
            auto bl = b.find("byteLength");
            if (bl == b.end() || !bl->is_number_unsigned())
                return what + ": byteLength is missing or not a whole number";
            uint64_t len = bl->get<uint64_t>();
            if (len > kMaxBufferSize)
                return what + ": byteLength " + std::to_string(len) + " is more than the " +
                       std::to_string(kMaxBufferSize >> 30) + " GiB a buffer may hold";
            if ((total += len) > kMaxExternalTotal)
                return what + ": the external buffers' byteLengths add up to more than the " +
                       std::to_string(kMaxExternalTotal >> 30) + " GiB a model may read";
            ext_buffer e{ i, u, "", "", len };
            std::string why = check_uri(*ctx, what, u, &e.path, true);
            if (!why.empty())
                return why;
            // what tinygltf's JoinPath makes of the folder and its own decoding of the uri
            e.asked = ctx->base + (ctx->base.back() == '/' ? "" : "/") +
                      tinygltf::dlib::urldecode(u);
            int fd = open_buffer(*ctx, e, &why);
            if (fd < 0)
                return why;
            close(fd);
            ctx->buffers.push_back(std::move(e));
        }
    auto images = j.find("images");
    if (images != j.end() && images->is_array())
        for (size_t i = 0; i < images->size(); i++) {
            const json &im = (*images)[i];
            auto uri = im.is_object() ? im.find("uri") : im.end();
            if (!im.is_object() || uri == im.end() || !uri->is_string())
                continue;
            const std::string &u = uri->get_ref<const std::string &>();
            if (u.empty() || tinygltf::IsDataURI(u))
                continue;
            std::string path, why = check_uri(*ctx, "image " + std::to_string(i), u, &path, false);
            if (!why.empty())
                return why;
        }
    return "";
}

// The callbacks: nothing exists but the checked buffers, each read once, in order.
bool fs_exists(const std::string &path, void *user)
{
    const fs_context *ctx = static_cast<const fs_context *>(user);
    for (const auto &b : ctx->buffers)
        if (b.asked == path)
            return true;
    return false;
}

std::string fs_expand(const std::string &path, void *)
{
    return path;
}

bool fs_read(std::vector<unsigned char> *out, std::string *err, const std::string &path, void *user)
{
    fs_context *ctx = static_cast<fs_context *>(user);
    if (ctx->next >= ctx->buffers.size() || ctx->buffers[ctx->next].asked != path) {
        // never expected: tinygltf 2.7.0 reads external buffers once each, in file order
        ctx->error = "tinygltf asked for '" + path + "', not the next checked buffer";
        if (err)
            *err += ctx->error;
        return false;
    }
    const ext_buffer &b = ctx->buffers[ctx->next++];
    std::string why;
    int fd = open_buffer(*ctx, b, &why); // checked again on the descriptor read
    if (fd < 0) {
        ctx->error = why;
        if (err)
            *err += why;
        return false;
    }
    out->resize(size_t(b.byte_length)); // checked: at most kMaxBufferSize, the file has it
    size_t got = 0;
    while (got < out->size()) {
        ssize_t r = read(fd, out->data() + got, out->size() - got);
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0) {
            ctx->error = "buffer " + std::to_string(b.index) + ": cannot read " +
                         quoted_uri(b.uri, b.path) + ": " +
                         (r < 0 ? std::strerror(errno) : "it shrank while being read");
            break;
        }
        got += size_t(r);
    }
    close(fd);
    if (got < out->size()) {
        if (err)
            *err += ctx->error;
        out->clear();
        return false;
    }
    return true;
}

bool fs_write(std::string *err, const std::string &path, const std::vector<unsigned char> &,
              void *user)
{
    fs_context *ctx = static_cast<fs_context *>(user);
    ctx->error = "tinygltf tried to write '" + path + "'; the loader never writes";
    if (err)
        *err += ctx->error;
    return false;
}

// Images are neither decoded nor kept: the loader ignores textures.
bool skip_image(tinygltf::Image *, const int, std::string *, std::string *, int, int,
                const unsigned char *, int, void *)
{
    return true;
}

} // namespace

// Everything the lg_gltf points to lives here, in containers whose elements do not move
// once made (deques, and vectors filled before their data() is taken).
struct lg_gltf_doc {
    tinygltf::Model model;
    lg_gltf view{};
    std::deque<lg_json> json_nodes;
    std::deque<std::vector<lg_json>> json_arrays;
    std::deque<std::vector<const char *>> key_arrays;
    std::vector<lg_gltf_buffer> buffers;
    std::vector<lg_gltf_view> views;
    std::vector<lg_gltf_accessor> accessors;
    std::vector<lg_gltf_mesh> meshes;
    std::deque<std::vector<lg_gltf_primitive>> primitives;
    std::vector<lg_gltf_node> nodes;
    std::vector<lg_gltf_scene> scenes;
    std::vector<lg_gltf_camera> cameras;
    std::vector<lg_gltf_material> materials;
    std::vector<lg_gltf_light> lights;
    std::vector<lg_gltf_animation> animations;
    std::deque<std::vector<lg_gltf_anim_channel>> anim_channels;
    std::deque<std::vector<lg_gltf_anim_sampler>> anim_samplers;
    std::vector<lg_gltf_skin> skins;
    std::vector<const char *> required;
    std::deque<tinygltf::Value> owned_values; // extension maps wrapped as objects
    std::string warnings;

    void convert(const tinygltf::Value &v, lg_json *out);
    const lg_json *value(const tinygltf::Value &v);
    const lg_json *extensions(const tinygltf::ExtensionMap &m);
    void fill();
    void fill_animations();
};

void lg_gltf_doc::convert(const tinygltf::Value &v, lg_json *out)
{
    *out = lg_json{};
    switch (v.Type()) {
    case tinygltf::BOOL_TYPE:
        out->type = LG_JSON_BOOL;
        out->boolean = v.Get<bool>();
        break;
    case tinygltf::INT_TYPE:
    case tinygltf::REAL_TYPE:
        out->type = LG_JSON_NUMBER;
        out->number = v.GetNumberAsDouble();
        break;
    case tinygltf::STRING_TYPE:
        out->type = LG_JSON_STRING;
        out->string = v.Get<std::string>().c_str();
        break;
    case tinygltf::ARRAY_TYPE: {
        const auto &a = v.Get<tinygltf::Value::Array>();
        json_arrays.emplace_back(a.size());
        std::vector<lg_json> &items = json_arrays.back();
        for (size_t i = 0; i < a.size(); i++)
            convert(a[i], &items[i]);
        out->type = LG_JSON_ARRAY;
        out->n = uint32_t(a.size());
        out->items = items.data();
        break;
    }
    case tinygltf::OBJECT_TYPE: {
        const auto &o = v.Get<tinygltf::Value::Object>();
        json_arrays.emplace_back(o.size());
        key_arrays.emplace_back(o.size());
        std::vector<lg_json> &items = json_arrays.back();
        std::vector<const char *> &keys = key_arrays.back();
        size_t i = 0;
        for (const auto &kv : o) {
            keys[i] = kv.first.c_str();
            convert(kv.second, &items[i]);
            i++;
        }
        out->type = LG_JSON_OBJECT;
        out->n = uint32_t(o.size());
        out->items = items.data();
        out->keys = keys.data();
        break;
    }
    default: break;
    }
}

const lg_json *lg_gltf_doc::value(const tinygltf::Value &v)
{
    if (v.Type() == tinygltf::NULL_TYPE)
        return nullptr;
    json_nodes.emplace_back();
    convert(v, &json_nodes.back());
    return &json_nodes.back();
}

const lg_json *lg_gltf_doc::extensions(const tinygltf::ExtensionMap &m)
{
    if (m.empty())
        return nullptr;
    owned_values.emplace_back(tinygltf::Value::Object(m.begin(), m.end()));
    return value(owned_values.back());
}

static void copy_numbers(const std::vector<double> &v, double *out, size_t cap, uint32_t *n)
{
    *n = uint32_t(v.size());
    for (size_t i = 0; i < v.size() && i < cap; i++)
        out[i] = v[i];
}

static uint32_t components_of(int type)
{
    switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
    }
}

static int32_t attribute(const tinygltf::Primitive &p, const char *name)
{
    auto it = p.attributes.find(name);
    return it == p.attributes.end() ? -1 : it->second;
}

void lg_gltf_doc::fill()
{
    const tinygltf::Model &m = model;
    for (const auto &b : m.buffers)
        buffers.push_back({ b.data.data(), b.data.size() });
    for (const auto &v : m.bufferViews)
        views.push_back({ v.buffer, v.byteOffset, v.byteLength, v.byteStride });
    for (const auto &a : m.accessors) {
        lg_gltf_accessor c{};
        c.name = a.name.c_str();
        c.view = a.bufferView;
        c.offset = a.byteOffset;
        c.component_type = a.componentType;
        c.components = components_of(a.type);
        c.normalized = a.normalized;
        c.count = a.count;
        c.sparse = a.sparse.isSparse;
        c.sparse_count = a.sparse.count;
        c.sparse_index_view = a.sparse.indices.bufferView;
        c.sparse_index_offset = a.sparse.indices.byteOffset;
        c.sparse_index_type = a.sparse.indices.componentType;
        c.sparse_value_view = a.sparse.values.bufferView;
        c.sparse_value_offset = a.sparse.values.byteOffset;
        accessors.push_back(c);
    }
    for (const auto &mesh : m.meshes) {
        primitives.emplace_back();
        std::vector<lg_gltf_primitive> &ps = primitives.back();
        for (const auto &p : mesh.primitives) {
            lg_gltf_primitive c{};
            c.mode = p.mode;
            c.indices = p.indices;
            c.material = p.material;
            c.position = attribute(p, "POSITION");
            c.normal = attribute(p, "NORMAL");
            c.texcoord = attribute(p, "TEXCOORD_0");
            c.n_targets = uint32_t(p.targets.size());
            c.extensions = extensions(p.extensions);
            ps.push_back(c);
        }
        meshes.push_back({ mesh.name.c_str(), ps.data(), uint32_t(ps.size()) });
    }
    for (const auto &n : m.nodes) {
        lg_gltf_node c{};
        c.name = n.name.c_str();
        c.mesh = n.mesh;
        c.camera = n.camera;
        c.skin = n.skin;
        c.children = n.children.data();
        c.n_children = uint32_t(n.children.size());
        copy_numbers(n.matrix, c.matrix, 16, &c.n_matrix);
        copy_numbers(n.translation, c.translation, 3, &c.n_translation);
        copy_numbers(n.rotation, c.rotation, 4, &c.n_rotation);
        copy_numbers(n.scale, c.scale, 3, &c.n_scale);
        c.extensions = extensions(n.extensions);
        nodes.push_back(c);
    }
    for (const auto &s : m.scenes)
        scenes.push_back(
            { s.name.c_str(), s.nodes.data(), uint32_t(s.nodes.size()), value(s.extras) });
    for (const auto &c : m.cameras) {
        lg_gltf_camera o{};
        o.name = c.name.c_str();
        o.type = c.type.c_str();
        o.yfov = c.perspective.yfov;
        o.aspect = c.perspective.aspectRatio;
        o.znear = c.perspective.znear;
        o.zfar = c.perspective.zfar;
        o.xmag = c.orthographic.xmag;
        o.ymag = c.orthographic.ymag;
        o.ortho_znear = c.orthographic.znear;
        o.ortho_zfar = c.orthographic.zfar;
        cameras.push_back(o);
    }
    for (const auto &mt : m.materials) {
        lg_gltf_material o{};
        o.name = mt.name.c_str();
        copy_numbers(mt.pbrMetallicRoughness.baseColorFactor, o.base_color, 4, &o.n_base_color);
        copy_numbers(mt.emissiveFactor, o.emissive, 3, &o.n_emissive);
        o.metallic = mt.pbrMetallicRoughness.metallicFactor;
        o.roughness = mt.pbrMetallicRoughness.roughnessFactor;
        o.double_sided = mt.doubleSided;
        o.extensions = extensions(mt.extensions);
        o.extras = value(mt.extras);
        materials.push_back(o);
    }
    for (const auto &l : m.lights) {
        lg_gltf_light o{};
        o.name = l.name.c_str();
        o.type = l.type.c_str();
        if (l.color.empty()) {
            o.n_color = 3;
            o.color[0] = o.color[1] = o.color[2] = 1.0;
        } else {
            copy_numbers(l.color, o.color, 3, &o.n_color);
        }
        o.intensity = l.intensity;
        o.range = l.range;
        o.inner_cone = l.spot.innerConeAngle;
        o.outer_cone = l.spot.outerConeAngle;
        lights.push_back(o);
    }
    for (const auto &r : m.extensionsRequired)
        required.push_back(r.c_str());

    lg_gltf &v = view;
    v.buffers = buffers.data();
    v.n_buffers = uint32_t(buffers.size());
    v.views = views.data();
    v.n_views = uint32_t(views.size());
    v.accessors = accessors.data();
    v.n_accessors = uint32_t(accessors.size());
    v.meshes = meshes.data();
    v.n_meshes = uint32_t(meshes.size());
    v.nodes = nodes.data();
    v.n_nodes = uint32_t(nodes.size());
    v.scenes = scenes.data();
    v.n_scenes = uint32_t(scenes.size());
    v.cameras = cameras.data();
    v.n_cameras = uint32_t(cameras.size());
    v.materials = materials.data();
    v.n_materials = uint32_t(materials.size());
    v.lights = lights.data();
    v.n_lights = uint32_t(lights.size());
    v.default_scene = m.defaultScene;
    v.extensions_required = required.data();
    v.n_extensions_required = uint32_t(required.size());
    v.extras = value(m.extras);
    v.asset_extras = value(m.asset.extras);
    v.warnings = warnings.c_str();
    fill_animations();
}

void lg_gltf_doc::fill_animations()
{
    for (const auto &a : model.animations) {
        anim_channels.emplace_back();
        std::vector<lg_gltf_anim_channel> &cs = anim_channels.back();
        for (const auto &c : a.channels)
            cs.push_back({ c.sampler, c.target_node, c.target_path.c_str() });
        anim_samplers.emplace_back();
        std::vector<lg_gltf_anim_sampler> &ss = anim_samplers.back();
        for (const auto &sm : a.samplers)
            ss.push_back({ sm.input, sm.output, sm.interpolation.c_str() });
        animations.push_back(
            { a.name.c_str(), cs.data(), uint32_t(cs.size()), ss.data(), uint32_t(ss.size()) });
    }
    view.animations = animations.data();
    view.n_animations = uint32_t(animations.size());
    for (const auto &sk : model.skins)
        skins.push_back({ sk.joints.data(), uint32_t(sk.joints.size()) });
    view.skins = skins.data();
    view.n_skins = uint32_t(skins.size());
}

extern "C" const lg_json *lg_json_get(const lg_json *obj, const char *key)
{
    if (!obj || obj->type != LG_JSON_OBJECT)
        return nullptr;
    for (uint32_t i = 0; i < obj->n; i++)
        if (std::strcmp(obj->keys[i], key) == 0)
            return &obj->items[i];
    return nullptr;
}

extern "C" lg_gltf_doc *lg_gltf_parse(const uint8_t *bytes, size_t size, const char *base_dir,
                                      const lg_gltf **out, char *err, size_t err_size)
{
    *out = nullptr;
    try {
        if (size > kMaxFileSize) {
            set_err(err, err_size, "%zu bytes: larger than the 2 GiB the loader reads", size);
            return nullptr;
        }
        bool glb = size >= 4 && std::memcmp(bytes, "glTF", 4) == 0;
        const uint8_t *json = bytes;
        size_t json_size = size;
        if (glb) {
            std::string why = check_glb(bytes, size, &json, &json_size);
            if (!why.empty()) {
                set_err(err, err_size, "%s", why.c_str());
                return nullptr;
            }
        }
        if (json_depth(json, json_size) > kMaxJsonDepth) {
            set_err(err, err_size, "JSON nested more than %d levels deep", kMaxJsonDepth);
            return nullptr;
        }
        fs_context fs;
        if (base_dir && *base_dir) {
            char real[PATH_MAX];
            if (!realpath(base_dir, real)) {
                set_err(err, err_size, "the model's folder '%s' cannot be resolved: %s", base_dir,
                        std::strerror(errno));
                return nullptr;
            }
            fs.base = real;
        }
        std::string refused = scan_refs(json, json_size, &fs);
        if (!refused.empty()) {
            set_err(err, err_size, "%s", refused.c_str());
            return nullptr;
        }
        std::string rewritten = without_draco_indices(json, json_size);
        std::vector<uint8_t> glb_copy;
        if (!rewritten.empty()) {
            if (glb) {
                glb_copy = replace_glb_json(bytes, size < rd32(bytes + 8) ? size : rd32(bytes + 8),
                                            json_size, rewritten);
                bytes = glb_copy.data();
                size = glb_copy.size();
            } else {
                bytes = reinterpret_cast<const uint8_t *>(rewritten.data());
                size = rewritten.size();
            }
            if (size > kMaxFileSize) {
                set_err(err, err_size, "%zu bytes: larger than the 2 GiB the loader reads", size);
                return nullptr;
            }
        }
        std::unique_ptr<lg_gltf_doc> doc(new lg_gltf_doc);
        tinygltf::TinyGLTF loader;
        loader.SetImageLoader(skip_image, nullptr);
        loader.SetFsCallbacks({ fs_exists, fs_expand, fs_read, fs_write, &fs });
        std::string terr, twarn;
        // without a folder, tinygltf gets one that cannot hold a file (and asks fs_exists,
        // which knows no file then)
        const std::string tbase = fs.base.empty() ? std::string("/nonexistent") : fs.base;
        bool ok =
            glb ? loader.LoadBinaryFromMemory(&doc->model, &terr, &twarn, bytes, unsigned(size),
                                              tbase, tinygltf::REQUIRE_VERSION)
                : loader.LoadASCIIFromString(&doc->model, &terr, &twarn,
                                             reinterpret_cast<const char *>(bytes), unsigned(size),
                                             tbase, tinygltf::REQUIRE_VERSION);
        if (!ok) {
            std::string why = fs.error.empty() ? one_line(terr) : fs.error;
            set_err(err, err_size, "%s",
                    why.empty() ? "tinygltf failed without a message" : why.c_str());
            return nullptr;
        }
        doc->warnings = one_line(twarn);
        doc->fill();
        *out = &doc->view;
        return doc.release();
    } catch (const std::bad_alloc &) {
        set_err(err, err_size, "out of memory while parsing");
    } catch (const std::exception &e) {
        set_err(err, err_size, "parse error: %s", e.what());
    } catch (...) {
        set_err(err, err_size, "parse error (unknown exception)");
    }
    return nullptr;
}

extern "C" void lg_gltf_doc_free(lg_gltf_doc *doc)
{
    delete doc;
}

// ---- Draco --------------------------------------------------------------------------------------

namespace
{

// Copies a Draco attribute into `dim` floats per point; checks the point-to-value mapping
// (a corrupt stream must not index past the attribute's values).
std::string extract(const draco::Mesh &mesh, int64_t id, int dim, const char *what, float *out)
{
    if (id < 0 || id > int64_t(UINT32_MAX))
        return std::string(what) + ": Draco attribute id " + std::to_string(id) + " is not valid";
    const draco::PointAttribute *a = mesh.GetAttributeByUniqueId(uint32_t(id));
    if (!a)
        return std::string(what) + ": the Draco stream has no attribute with id " +
               std::to_string(id);
    if (a->num_components() < 1)
        return std::string(what) + ": the Draco attribute has no components";
    if (!a->is_mapping_identity() && a->indices_map_size() < mesh.num_points())
        return std::string(what) + ": the Draco attribute maps fewer points than the mesh has";
    float tmp[16];
    for (draco::PointIndex i(0); i < mesh.num_points(); ++i) {
        draco::AttributeValueIndex v = a->mapped_index(i);
        if (v.value() >= a->size())
            return std::string(what) + ": point " + std::to_string(i.value()) +
                   " maps past the attribute's values";
        int n = a->num_components() < 16 ? a->num_components() : 16;
        if (!a->ConvertValue<float>(v, int8_t(n), tmp))
            return std::string(what) + ": cannot convert point " + std::to_string(i.value()) +
                   " to float";
        for (int k = 0; k < dim; k++)
            out[size_t(i.value()) * dim + k] = k < n ? tmp[k] : 0.0f;
    }
    return "";
}

} // namespace

extern "C" void lg_draco_mesh_free(lg_draco_mesh *m)
{
    if (!m)
        return;
    free(m->positions);
    free(m->normals);
    free(m->texcoords);
    free(m->indices);
    *m = lg_draco_mesh{};
}

extern "C" int lg_draco_decode(const uint8_t *bytes, size_t size, int64_t position_id,
                               int64_t normal_id, int64_t texcoord_id, uint64_t max_points,
                               uint64_t max_faces, lg_draco_mesh *out, char *err, size_t err_size)
{
    *out = lg_draco_mesh{};
    try {
        draco::DecoderBuffer buf;
        buf.Init(reinterpret_cast<const char *>(bytes), size);
        auto type = draco::Decoder::GetEncodedGeometryType(&buf);
        if (!type.ok()) {
            set_err(err, err_size, "Draco: %s", type.status().error_msg());
            return -1;
        }
        if (type.value() != draco::TRIANGULAR_MESH) {
            set_err(err, err_size, "Draco: the stream holds a point cloud, not a triangle mesh");
            return -1;
        }
        draco::Decoder decoder;
        auto res = decoder.DecodeMeshFromBuffer(&buf);
        if (!res.ok()) {
            set_err(err, err_size, "Draco decoding failed: %s", res.status().error_msg());
            return -1;
        }
        const draco::Mesh &mesh = *res.value();
        uint64_t np = mesh.num_points(), nf = mesh.num_faces();
        if (np > max_points || nf > max_faces) {
            set_err(err, err_size,
                    "Draco: %llu points and %llu triangles, more than the %llu and %llu accepted",
                    (unsigned long long)np, (unsigned long long)nf, (unsigned long long)max_points,
                    (unsigned long long)max_faces);
            return -1;
        }
        out->n_points = uint32_t(np);
        out->n_faces = uint32_t(nf);
        out->positions = static_cast<float *>(malloc((np ? np : 1) * 3 * sizeof(float)));
        out->indices = static_cast<uint32_t *>(malloc((nf ? nf : 1) * 3 * sizeof(uint32_t)));
        if (normal_id >= 0)
            out->normals = static_cast<float *>(malloc((np ? np : 1) * 3 * sizeof(float)));
        if (texcoord_id >= 0)
            out->texcoords = static_cast<float *>(malloc((np ? np : 1) * 2 * sizeof(float)));
        if (!out->positions || !out->indices || (normal_id >= 0 && !out->normals) ||
            (texcoord_id >= 0 && !out->texcoords)) {
            lg_draco_mesh_free(out);
            set_err(err, err_size, "out of memory for %llu Draco points", (unsigned long long)np);
            return -1;
        }
        std::string why = extract(mesh, position_id, 3, "POSITION", out->positions);
        if (why.empty() && normal_id >= 0)
            why = extract(mesh, normal_id, 3, "NORMAL", out->normals);
        if (why.empty() && texcoord_id >= 0)
            why = extract(mesh, texcoord_id, 2, "TEXCOORD_0", out->texcoords);
        for (draco::FaceIndex f(0); why.empty() && f < mesh.num_faces(); ++f) {
            const draco::Mesh::Face &face = mesh.face(f);
            for (int k = 0; k < 3; k++) {
                uint32_t v = face[k].value();
                if (v >= np) {
                    why = "triangle " + std::to_string(f.value()) + " uses point " +
                          std::to_string(v) + " of " + std::to_string(np);
                    break;
                }
                out->indices[size_t(f.value()) * 3 + k] = v;
            }
        }
        if (!why.empty()) {
            lg_draco_mesh_free(out);
            set_err(err, err_size, "Draco: %s", why.c_str());
            return -1;
        }
        return 0;
    } catch (const std::bad_alloc &) {
        set_err(err, err_size, "out of memory while decoding Draco");
    } catch (const std::exception &e) {
        set_err(err, err_size, "Draco decoding failed: %s", e.what());
    } catch (...) {
        set_err(err, err_size, "Draco decoding failed (unknown exception)");
    }
    lg_draco_mesh_free(out);
    return -1;
}
