/* lg_gl_program (lightgraph/gl.h): compile and link with file names in messages. */
#include "lightgraph/gl.h"

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *stage_name(GLenum stage)
{
    switch (stage) {
    case GL_VERTEX_SHADER: return "vertex shader";
    case GL_TESS_CONTROL_SHADER: return "tessellation control shader";
    case GL_TESS_EVALUATION_SHADER: return "tessellation evaluation shader";
    case GL_GEOMETRY_SHADER: return "geometry shader";
    case GL_FRAGMENT_SHADER: return "fragment shader";
    case GL_COMPUTE_SHADER: return "compute shader";
    default: return NULL;
    }
}

/* Finds the line whose first token is #version. On success *after is the offset just
 * past that line (its newline included, if any) and *line its 1-based number. */
static bool find_version_line(const char *src, size_t *after, unsigned *line)
{
    unsigned n = 1;
    for (const char *p = src; *p; n++) {
        const char *q = p;
        while (*q == ' ' || *q == '\t')
            q++;
        bool is_version = false;
        if (*q == '#') {
            q++;
            while (*q == ' ' || *q == '\t')
                q++;
            is_version = strncmp(q, "version", 7) == 0 && (q[7] == ' ' || q[7] == '\t');
        }
        const char *end = strchr(p, '\n');
        if (is_version) {
            *after = end ? (size_t)(end + 1 - src) : strlen(src);
            *line = n;
            return true;
        }
        if (!end)
            break;
        p = end + 1;
    }
    return false;
}

/* A malloc'd copy of the object's info log without trailing blanks, or NULL. */
static char *info_log(const lg_gl *gl, GLuint obj, bool program)
{
    GLint len = 0;
    if (program)
        gl->GetProgramiv(obj, GL_INFO_LOG_LENGTH, &len);
    else
        gl->GetShaderiv(obj, GL_INFO_LOG_LENGTH, &len);
    if (len <= 0)
        return NULL;
    char *log = malloc((size_t)len + 1);
    if (!log)
        return NULL;
    GLsizei got = 0;
    if (program)
        gl->GetProgramInfoLog(obj, len, &got, log);
    else
        gl->GetShaderInfoLog(obj, len, &got, log);
    if (got < 0)
        got = 0;
    log[got] = '\0';
    while (got > 0 && (log[got - 1] == '\n' || log[got - 1] == ' ' || log[got - 1] == '\r'))
        log[--got] = '\0';
    if (got == 0) {
        free(log);
        return NULL;
    }
    return log;
}

/* Compiles one stage; returns the shader or 0 after reporting. */
static GLuint compile(lg_node *node, const lg_gl *gl, const lg_gl_shader_src *src, const char *name,
                      const char *defines)
{
    const char *strings[3];
    GLint lengths[3];
    GLsizei count = 0;
    char *middle = NULL;

    if (defines && defines[0]) {
        size_t after;
        unsigned line;
        if (!find_version_line(src->source, &after, &line)) {
            lg_error(node, "%s: no #version line to insert the defines after", name);
            return 0;
        }
        /* GLSL 3.30 and later: the line after "#line N" is line N, so the line after
         * the defines is numbered as it is in the file. */
        bool newline = after > 0 && src->source[after - 1] == '\n';
        size_t dlen = strlen(defines);
        bool dnewline = defines[dlen - 1] == '\n';
        size_t mlen = dlen + 32;
        middle = malloc(mlen);
        if (!middle) {
            lg_error(node, "%s: out of memory", name);
            return 0;
        }
        int n = snprintf(middle, mlen, "%s%s%s#line %u\n", newline ? "" : "\n", defines,
                         dnewline ? "" : "\n", line + 1);
        strings[0] = src->source;
        lengths[0] = (GLint)after;
        strings[1] = middle;
        lengths[1] = n;
        strings[2] = src->source + after;
        lengths[2] = (GLint)strlen(src->source + after);
        count = 3;
    } else {
        strings[0] = src->source;
        lengths[0] = -1; /* NUL-terminated */
        count = 1;
    }

    GLuint shader = gl->CreateShader(src->stage);
    if (!shader) {
        lg_error(node, "%s: glCreateShader(%s) failed", name, stage_name(src->stage));
        free(middle);
        return 0;
    }
    gl->ShaderSource(shader, count, strings, lengths);
    free(middle);
    gl->CompileShader(shader);
    GLint ok = GL_FALSE;
    gl->GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    char *log = info_log(gl, shader, false);
    if (!ok) {
        lg_error(node, "%s: %s compile failed:\n%s", name, stage_name(src->stage),
                 log ? log : "(empty info log)");
        free(log);
        gl->DeleteShader(shader);
        return 0;
    }
    if (log)
        lg_log(node, LG_LOG_WARN, "%s: %s compiled with messages:\n%s", name,
               stage_name(src->stage), log);
    free(log);
    return shader;
}

GLuint lg_gl_program(lg_node *node, const lg_gl *gl, const lg_gl_shader_src *stages, unsigned count,
                     const char *defines)
{
    if (!node)
        return 0;
    if (!gl) {
        lg_error(node, "lg_gl_program: no GL context");
        return 0;
    }
    if (!stages || count == 0) {
        lg_error(node, "lg_gl_program: no shader stages given");
        return 0;
    }
    /* Names for messages: "a.vert + a.frag". */
    char names[512] = "";
    size_t used = 0;
    for (unsigned i = 0; i < count; i++) {
        char fallback[32];
        const char *name = stages[i].name;
        if (!name) {
            snprintf(fallback, sizeof fallback, "<stage %u>", i);
            name = fallback;
        }
        if (!stage_name(stages[i].stage)) {
            lg_error(node, "%s: unknown shader stage 0x%x", name, (unsigned)stages[i].stage);
            return 0;
        }
        if (!stages[i].source) {
            lg_error(node, "%s: no source", name);
            return 0;
        }
        if (used < sizeof names) {
            int n = snprintf(names + used, sizeof names - used, "%s%s", i ? " + " : "", name);
            used += n > 0 ? (size_t)n : 0;
        }
    }

    GLuint *shaders = calloc(count, sizeof *shaders);
    if (!shaders) {
        lg_error(node, "%s: out of memory", names);
        return 0;
    }
    GLuint program = 0;
    unsigned compiled = 0;
    for (; compiled < count; compiled++) {
        char fallback[32];
        const char *name = stages[compiled].name;
        if (!name) {
            snprintf(fallback, sizeof fallback, "<stage %u>", compiled);
            name = fallback;
        }
        shaders[compiled] = compile(node, gl, &stages[compiled], name, defines);
        if (!shaders[compiled])
            goto done;
    }

    program = gl->CreateProgram();
    if (!program) {
        lg_error(node, "%s: glCreateProgram failed", names);
        goto done;
    }
    for (unsigned i = 0; i < count; i++)
        gl->AttachShader(program, shaders[i]);
    gl->LinkProgram(program);
    /* The program keeps what it linked; the shader objects are no longer needed. */
    for (unsigned i = 0; i < count; i++)
        gl->DetachShader(program, shaders[i]);
    GLint ok = GL_FALSE;
    gl->GetProgramiv(program, GL_LINK_STATUS, &ok);
    char *log = info_log(gl, program, true);
    if (!ok) {
        lg_error(node, "%s: link failed:\n%s", names, log ? log : "(empty info log)");
        gl->DeleteProgram(program);
        program = 0;
    } else if (log) {
        lg_log(node, LG_LOG_WARN, "%s: linked with messages:\n%s", names, log);
    }
    free(log);

done:
    for (unsigned i = 0; i < compiled; i++)
        if (shaders[i])
            gl->DeleteShader(shaders[i]);
    free(shaders);
    return program;
}
