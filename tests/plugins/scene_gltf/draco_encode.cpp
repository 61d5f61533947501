// draco_encode.cpp: libdraco's encoder for test_gltf_textures (the loader only decodes): a
// triangle soup with positions, normals, two texture coordinate sets and tangents, encoded
// without quantisation (the values come back exactly).
#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>

#include <cstdlib>
#include <cstring>

#include "draco_encode.h"

extern "C" int gt_draco_encode(uint32_t n_faces, const float *pos, const float *nrm,
                               const float *uv0, const float *uv1, const float *tan, uint8_t **out,
                               size_t *size, int ids[5])
{
    try {
        draco::TriangleSoupMeshBuilder b;
        b.Start(int(n_faces));
        int a[5] = {
            b.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32),
            b.AddAttribute(draco::GeometryAttribute::NORMAL, 3, draco::DT_FLOAT32),
            b.AddAttribute(draco::GeometryAttribute::TEX_COORD, 2, draco::DT_FLOAT32),
            b.AddAttribute(draco::GeometryAttribute::TEX_COORD, 2, draco::DT_FLOAT32),
            b.AddAttribute(draco::GeometryAttribute::GENERIC, 4, draco::DT_FLOAT32),
        };
        const float *src[5] = { pos, nrm, uv0, uv1, tan };
        const int dim[5] = { 3, 3, 2, 2, 4 };
        for (uint32_t f = 0; f < n_faces; f++)
            for (int k = 0; k < 5; k++) {
                const float *v = src[k] + size_t(f) * 3 * dim[k];
                b.SetAttributeValuesForFace(a[k], draco::FaceIndex(f), v, v + dim[k],
                                            v + 2 * dim[k]);
            }
        std::unique_ptr<draco::Mesh> mesh = b.Finalize();
        if (!mesh)
            return -1;
        draco::Encoder enc;
        enc.SetSpeedOptions(10, 10);
        draco::EncoderBuffer buf;
        if (!enc.EncodeMeshToBuffer(*mesh, &buf).ok())
            return -1;
        for (int k = 0; k < 5; k++)
            ids[k] = int(mesh->attribute(a[k])->unique_id());
        *size = buf.size();
        *out = static_cast<uint8_t *>(malloc(buf.size()));
        if (!*out)
            return -1;
        memcpy(*out, buf.data(), buf.size());
        return 0;
    } catch (...) {
        return -1;
    }
}
