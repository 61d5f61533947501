/* Test plugin "testfile": a node that writes a file through the host (an output-file
 * parameter, lg_output_file_write, ABI 2.7) and passes its image through, so that the
 * tests can check where and when such a file appears: checked before anything runs,
 * committed with the render's outputs, never left behind by a failure.
 *
 *   test_file_writer { image = X, file = "dump.txt", text = "...", fail = false,
 *                      wrong_key = false }
 *
 * file: written with `text` when not ""; fail: the node fails after writing (a failure
 * later in the render than the write); wrong_key: writes through a parameter that is not an
 * output file (the host must refuse). */
#include <string.h>

#include "lightgraph/lightgraph.h"

static const lg_param_desc params[] = {
    { .key = "file",
      .type = LG_PARAM_PATH,
      .def.s = "",
      .role = LG_ROLE_OUTPUT_FILE,
      .doc = "the file written (\"\" none)" },
    { .key = "text",
      .type = LG_PARAM_STRING,
      .def.s = "written by test_file_writer\n",
      .doc = "its content" },
    { .key = "fail",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "fail in execute, after writing the file" },
    { .key = "wrong_key",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "write through the parameter 'text' instead (not an output file)" },
};
static const lg_port_desc in[] = { { .name = "image", .kind = LG_KIND_IMAGE } };
static const lg_port_desc out[] = { { .name = "out", .kind = LG_KIND_IMAGE } };

static int prepare(lg_node *n)
{
    lg_resource_info info;
    lg_describe(lg_input(n, 0), &info, n);
    lg_image_desc d = { .width = info.image.width,
                        .height = info.image.height,
                        .format = LG_FORMAT_RGBA32F };
    return lg_declare_image(n, 0, &d);
}

static int execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    const char *text = lg_param_string(n, "text");
    int rc = 0;
    if (lg_param_bool(n, "wrong_key"))
        rc = lg_output_file_write(n, "text", text, strlen(text));
    else if (lg_param_string(n, "file")[0])
        rc = lg_output_file_write(n, "file", text, strlen(text));
    if (rc)
        return rc;
    if (lg_param_bool(n, "fail"))
        return lg_error(n, "test_file_writer: failing as asked (fail = true), after the write");
    lg_resource_info info;
    lg_describe(lg_input(n, 0), &info, n);
    size_t np = (size_t)info.image.width * info.image.height;
    lg_cpu_view a, b;
    if ((rc = lg_map_cpu(n, lg_input(n, 0), LG_READ, &a)) ||
        (rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &b)))
        return rc;
    const float *p = a.pixels;
    float *q = b.pixels;
    for (size_t i = 0; i < 4 * np; i++)
        q[i] = info.image.format == LG_FORMAT_RGBA32F ? p[i] : 0.0f;
    return 0;
}

static const lg_node_type types[] = { {
    .struct_size = sizeof(lg_node_type),
    .name = "test_file_writer",
    .doc = "Writes a file through the host's outputs and passes its image through (test)",
    LG_PARAMS(params),
    LG_INPUTS(in),
    LG_OUTPUTS(out),
    .prepare = prepare,
    .execute = execute,
} };

LG_PLUGIN_DEFINE("testfile", "1.0.0", "Output-file API test node", types)
