/* host/viewer/picture.c: the shown image, read: the texture the display draws (the
 * image's own GL texture, or a CPU copy), auto exposure, and the screenshots of the shown
 * image (PNG as displayed, EXR linear) and of the window. Files are written all or nothing
 * through exec/outputs.h, as the render command writes its outputs.
 */
#include "viewer/state.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "exec/outputs.h"
#include "lightgraph/image.h"
#include "lightgraph/kinds.h"

lg_resource *lg_viewer_shown_resource(const loaded *l, lg_pnode **mapper)
{
    lg_resource *r = lg_edge_resource(l->ex, l->shown);
    if (mapper)
        *mapper = r ? (r->parts.parent ? r->parts.parent->producer : r->producer) : NULL;
    return r;
}

/* A CPU copy of the shown resource r, RGBA32F, as the output files are written: a probe
 * through its file layout, an image as it is. Returns 0 with *img (free it with
 * cpu_copy_free), or -1 with err. */
static int cpu_copy(viewer *v, lg_resource *r, lg_image *img, char *err, size_t errlen)
{
    *img = (lg_image){ 0, 0, NULL };
    if (r->kind == LG_KIND_PROBE)
        return lg_resource_probe_file(v->cur.ex, r, img, err, errlen) ? -1 : 0;
    float *px = NULL;
    if (lg_resource_to_rgba32f(v->cur.ex, r, &px, err, errlen))
        return -1;
    *img = (lg_image){ r->image.width, r->image.height, px };
    return 0;
}

static void cpu_copy_free(const lg_resource *r, lg_image *img)
{
    if (r->kind == LG_KIND_PROBE)
        lg_image_free(img);
    else
        free(img->pixels);
}

/* Writes img to path all or nothing (a file of its own set in exec/outputs.h). */
static int write_image(const char *path, const lg_image *img, const lg_image_write_opts *wo,
                       char *err, size_t errlen)
{
    lg_outputs *o = lg_outputs_new();
    int rc = lg_outputs_add(o, path, LG_OUTPUT_IMAGE, err, errlen);
    if (rc == 0)
        rc = lg_outputs_write_image(o, path, img, wo, err, errlen);
    if (rc == 0)
        rc = lg_outputs_commit(o, err, errlen);
    lg_outputs_free(&o);
    return rc;
}

int lg_viewer_shown_texture(viewer *v, uint32_t *tex, uint32_t *w, uint32_t *h, char *err,
                            size_t errlen)
{
    lg_pnode *mapper;
    lg_resource *r = lg_viewer_shown_resource(&v->cur, &mapper);
    if (!r || !mapper) {
        snprintf(err, errlen, "the shown output '%s' has no resource", v->cur.shown_name);
        return -1;
    }
    const GladGLContext *gl = lg_gl_device_table(v->gl);
    if (r->kind == LG_KIND_IMAGE && !(r->image.flags & (LG_IMAGE_CUBE | LG_IMAGE_DEPTH_ONLY)) &&
        (r->image.format == LG_FORMAT_RGBA32F || r->image.format == LG_FORMAT_RGBA16F ||
         r->image.format == LG_FORMAT_RGBA8)) {
        uint32_t name = 0;
        if (lg_resource_map_gl(v->cur.ex, mapper, r, LG_READ, &name, NULL) != 0 || !name) {
            snprintf(err, errlen, "the shown output '%s' cannot be mapped on GL",
                     v->cur.shown_name);
            return -1;
        }
        *tex = name;
        *w = r->image.width;
        *h = r->image.height;
        return 0;
    }
    /* other formats and kinds: through the CPU, as the output files are written; only when
     * the producer ran (the texture keeps the last copy) */
    if (!v->cpu_tex || mapper->viewer.ran_this_frame) {
        lg_image img;
        if (cpu_copy(v, r, &img, err, errlen))
            return -1;
        if (!v->cpu_tex)
            gl->GenTextures(1, &v->cpu_tex);
        gl->BindTexture(GL_TEXTURE_2D, v->cpu_tex);
        gl->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, (GLsizei)img.width, (GLsizei)img.height, 0,
                       GL_RGBA, GL_FLOAT, img.pixels);
        gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        gl->BindTexture(GL_TEXTURE_2D, 0);
        v->cpu_tex_w = img.width;
        v->cpu_tex_h = img.height;
        cpu_copy_free(r, &img);
    }
    *tex = v->cpu_tex;
    *w = v->cpu_tex_w;
    *h = v->cpu_tex_h;
    return 0;
}

/* Auto exposure for an image that is not display-referred: the stops that put its
 * log-average luminance at 0.18 (Reinhard's key), from a CPU copy. */
void lg_viewer_auto_exposure(viewer *v)
{
    v->ev_auto_pending = false;
    if (v->cur.display_referred) {
        v->ev = 0;
        return;
    }
    lg_resource *r = lg_viewer_shown_resource(&v->cur, NULL);
    float *px = NULL;
    char err[512];
    if (!r || r->kind != LG_KIND_IMAGE ||
        lg_resource_to_rgba32f(v->cur.ex, r, &px, err, sizeof err))
        return;
    double sum = 0;
    size_t n = (size_t)r->image.width * r->image.height, used = 0;
    for (size_t i = 0; i < n; i++) {
        double y = 0.2126 * px[4 * i] + 0.7152 * px[4 * i + 1] + 0.0722 * px[4 * i + 2];
        if (isfinite(y) && y >= 0) {
            sum += log(1e-4 + y);
            used++;
        }
    }
    free(px);
    if (used) {
        double avg = exp(sum / (double)used);
        double ev = log2(0.18 / avg);
        v->ev = (float)(isfinite(ev) ? fmax(-20, fmin(20, ev)) : 0);
    }
}

/* ---- screenshots ----------------------------------------------------------------------------- */

int lg_viewer_screenshot(viewer *v, const char *path, char *err, size_t errlen)
{
    lg_resource *r = lg_viewer_shown_resource(&v->cur, NULL);
    if (!r) {
        snprintf(err, errlen, "nothing is shown");
        return -1;
    }
    lg_image img;
    if (cpu_copy(v, r, &img, err, errlen))
        return -1;
    lg_file_format fmt = lg_image_format_from_path(path);
    if (fmt == LG_FILE_PNG) {
        float k = exp2f(v->ev);
        size_t n = (size_t)img.width * img.height * 4;
        for (size_t i = 0; i < n; i++)
            if (i % 4 != 3)
                img.pixels[i] *= k;
    }
    lg_image_write_opts wo;
    memset(&wo, 0, sizeof wo);
    wo.exr_pixel = LG_EXR_FLOAT;
    int rc = write_image(path, &img, &wo, err, errlen);
    cpu_copy_free(r, &img);
    return rc;
}

/* The window's pixels as shown, read back after drawing and before the swap. */
int lg_viewer_window_screenshot(viewer *v, const char *path, char *err, size_t errlen)
{
    const GladGLContext *gl = lg_gl_device_table(v->gl);
    int w, h;
    glfwGetFramebufferSize(v->win, &w, &h);
    unsigned char *rgba = lg_xmalloc((size_t)w * h * 4);
    gl->BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    gl->ReadBuffer(GL_BACK);
    gl->PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl->ReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    lg_image img = { (uint32_t)w, (uint32_t)h, lg_xmalloc((size_t)w * h * 4 * sizeof(float)) };
    /* bottom-up to top-down; the PNG writer encodes linear values: decode what is shown */
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w * 4; x++) {
            unsigned char b = rgba[(size_t)(h - 1 - y) * w * 4 + x];
            img.pixels[(size_t)y * w * 4 + x] = x % 4 == 3 ? 1.0f : lg_srgb_decode(b / 255.0f);
        }
    free(rgba);
    lg_image_write_opts wo;
    memset(&wo, 0, sizeof wo);
    int rc = write_image(path, &img, &wo, err, errlen);
    free(img.pixels);
    return rc;
}
