// Index maps, stage 1: the raster pass (index_map_renderer.cpp describes
// the whole; index_map_renderer_impl.h holds the shared state).

#include "index_map_renderer_impl.h"

namespace svit::gl {
namespace {

// A face's rows (right, up, forward in world) and frustum.
struct FaceSetup {
  glm::dvec3 rows[3];
  glm::dvec3 eye;
  Frustum frustum;
};

FaceSetup faceSetup(const PreparedSample& s, int face) {
  FaceSetup f;
  const FaceBasis basis = cubeFaceBasis(face);
  f.rows[0] = s.world_from_cube * basis.right;
  f.rows[1] = s.world_from_cube * basis.up;
  f.rows[2] = s.world_from_cube * basis.forward;
  f.eye = glm::dvec3(s.gpu.position_near[0], s.gpu.position_near[1], s.gpu.position_near[2]);
  f.frustum = faceFrustum(f.eye, f.rows[0], f.rows[1], f.rows[2], s.gpu.position_near[3],
                          isHalfFace(s.layout, face), s.layout == MapLayout::kParallel,
                          s.gpu.cube_y_half[3], s.gpu.cube_x_far[3]);
  return f;
}

}  // namespace

void IndexMapRenderer::Impl::render(std::span<const PreparedSample> batch, GatherStats& stats) {
  bindRasterTarget();
  batch_drawn.assign(batch.size() * chunks.size(), 0);
  pending_faces.clear();
  buildSetIndices(batch, stats);
  rasterFaces(batch, stats);
  rasterOcclusionRounds(batch, stats);
}

void IndexMapRenderer::Impl::bindRasterTarget() const {
  const int res = settings.resolution;
  glUseProgram(raster.id());
  glBindVertexArray(vao.id());
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kReceiversBinding, receivers.id());
  glViewport(0, 0, res, res);
}

void IndexMapRenderer::Impl::useSample(const PreparedSample& s) const {
  const GLuint program = raster.id();
  glProgramUniform3f(program, 0, s.gpu.position_near[0], s.gpu.position_near[1],
                     s.gpu.position_near[2]);
  glProgramUniform1i(program, 2, s.layout == MapLayout::kParallel ? 1 : 0);
  glProgramUniform1f(program, 3, s.gpu.position_near[3]);
  glProgramUniform1f(program, 4, s.gpu.cube_x_far[3]);
  glProgramUniform1f(program, 5, s.gpu.cube_y_half[3]);
}

void IndexMapRenderer::Impl::useLayer(GLint layer, int first_row) const {
  const int res = settings.resolution;
  glNamedFramebufferTextureLayer(fbo.id(), GL_COLOR_ATTACHMENT0, id_map.id(), 0, layer);
  glNamedFramebufferTextureLayer(fbo.id(), GL_DEPTH_ATTACHMENT, depth_map.id(), 0, layer);
  // Half faces: only the rows above the horizon are drawn, cleared and reduced.
  glScissor(0, first_row, res, res - first_row);
}

void IndexMapRenderer::Impl::drawForSample(std::span<const PreparedSample> batch, size_t b,
                                           std::span<const uint32_t> list, GatherStats& stats) {
  for (uint32_t i : list) batch_drawn[b * chunks.size() + i] = 1;
  stats.triangles_drawn += drawChunks(list, batch[b].gpu.info[3]);
}

void IndexMapRenderer::Impl::buildSetIndices(std::span<const PreparedSample> batch,
                                             GatherStats& stats) {
  batch_indices.clear();
  face_index_ranges.assign(batch.size() * kCubeFaceCount, {0u, 0u});
  for (size_t b = 0; b < batch.size(); ++b) {
    const PreparedSample& s = batch[b];
    if (!s.static_triangles) continue;
    const LayoutFaces faces = layoutFaces(s.layout);
    for (int i = 0; i < faces.count; ++i) {
      const int face = faces.faces[size_t(i)];
      const FaceSetup setup = faceSetup(s, face);
      const Frustum& frustum = setup.frustum;
      candidateChunks(chunks, frustum, s.reach_lo, s.reach_hi, s.static_triangles, face_chunks);
      const size_t first = batch_indices.size();
      // The set's triangles first, each static chunk's drawn ones boxed;
      // then the dynamic chunks that may stand in front of them.
      seen_boxes.clear();
      for (uint32_t c : face_chunks) {
        if (chunks[c].dynamic) continue;
        Box box;
        const uint64_t drawn = appendSetIndices(chunks[c], static_positions, frustum, s.gpu.info[3],
                                                *s.static_triangles, batch_indices, &box);
        if (drawn == 0) continue;
        batch_drawn[b * chunks.size() + c] = 1;
        stats.triangles_drawn += drawn;
        seen_boxes.push_back(box);
      }
      if (s.layout != MapLayout::kParallel)
        keepDynamicBeforeSet(chunks, setup.eye, seen_boxes, face_chunks);
      for (uint32_t c : face_chunks) {
        if (!chunks[c].dynamic) continue;
        batch_drawn[b * chunks.size() + c] = 1;
        stats.triangles_drawn +=
            appendSetIndices(chunks[c], static_positions, frustum, s.gpu.info[3],
                             *s.static_triangles, batch_indices);
      }
      face_index_ranges[b * kCubeFaceCount + size_t(face)] = {
          uint32_t(first), uint32_t(batch_indices.size() - first)};
    }
  }
  if (!batch_indices.empty()) {
    reserveUints(set_indices, set_indices_capacity, batch_indices.size());
    glNamedBufferSubData(set_indices.id(), 0, GLsizeiptr(batch_indices.size() * sizeof(uint32_t)),
                         batch_indices.data());
  }
}

void IndexMapRenderer::Impl::rasterFaces(std::span<const PreparedSample> batch,
                                         GatherStats& stats) {
  const int res = settings.resolution;
  const GLuint program = raster.id();
  const GLuint clear_id[4] = {kNoReceiver, kNoTriangle, 0, 0};
  const GLfloat clear_depth = 0.0f;  // reversed depth: 0 = infinitely far
  for (size_t b = 0; b < batch.size(); ++b) {
    const PreparedSample& s = batch[b];
    const bool parallel = s.layout == MapLayout::kParallel;
    useSample(s);
    const LayoutFaces faces = layoutFaces(s.layout);
    for (int i = 0; i < faces.count; ++i) {
      const int face = faces.faces[size_t(i)];
      const GLint layer = GLint(b * kCubeFaceCount + size_t(face));
      const int first_row = firstRow(s.layout, face, res);
      useLayer(layer, first_row);
      glClearBufferuiv(GL_COLOR, 0, clear_id);
      glClearBufferfv(GL_DEPTH, 0, &clear_depth);
      const FaceSetup setup = faceSetup(s, face);
      const glm::dvec3* rows = setup.rows;
      const glm::dvec3& eye = setup.eye;
      PendingFace pending;
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c)
          pending.view_from_world[size_t(r * 3 + c)] = GLfloat(rows[r][c]);
      }
      // row-major rows
      glProgramUniformMatrix3fv(program, 1, 1, GL_TRUE, pending.view_from_world.data());
      if (s.static_triangles) {
        // Its index list, from buildSetIndices: only what the sample saw.
        const auto [first, count] = face_index_ranges[b * kCubeFaceCount + size_t(face)];
        if (count > 0) {
          glDrawElements(GL_TRIANGLES, GLsizei(count), GL_UNSIGNED_INT,
                         reinterpret_cast<const void*>(uintptr_t(first) * sizeof(uint32_t)));
        }
      } else {
        candidateChunks(chunks, setup.frustum, s.reach_lo, s.reach_hi, nullptr, face_chunks);
        // Occlusion culling where it can spare much: perspective faces
        // drawing many chunks.
        if (settings.occlusion_culling && !parallel && face_chunks.size() >= kOcclusionMinChunks) {
          splitNearest(chunks, face_chunks, eye, occlusionFirstTriangles(chunks, face_chunks),
                       near_chunks, pending.rest);
          drawForSample(batch, b, near_chunks, stats);
          pending.sample = b;
          pending.layer = layer;
          pending.first_row = first_row;
          pending.face = {eye, rows[0], rows[1], rows[2], 1.0, 1.0, double(s.gpu.position_near[3])};
          pending_faces.push_back(std::move(pending));
        } else {
          drawForSample(batch, b, face_chunks, stats);
        }
      }
      ++stats.faces_rendered;
      stats.texels += uint64_t(res) * uint64_t(res - first_row);
      batch_layers.push_back({uint32_t(b), uint32_t(face), uint32_t(first_row), uint32_t(layer)});
    }
  }
}

// Rounds: each reads back the faces' depth (one sync per batch, not per
// face), leaves out what it hides, and draws the nearest of the rest (the
// last round: all of it), so the occluders build up front to back.
void IndexMapRenderer::Impl::rasterOcclusionRounds(std::span<const PreparedSample> batch,
                                                   GatherStats& stats) {
  const int res = settings.resolution;
  const GLuint program = raster.id();
  depth_scratch.resize(size_t(res) * size_t(res));
  size_t current = batch.size();
  for (int round = 1; round <= kOcclusionRounds && !pending_faces.empty(); ++round) {
    // Every face's test first, then every face's draw: a read-back after a
    // draw would wait for it, face by face.
    for (PendingFace& p : pending_faces) {
      glGetTextureSubImage(depth_map.id(), 0, 0, 0, p.layer, res, res, 1, GL_DEPTH_COMPONENT,
                           GL_FLOAT, GLsizei(depth_scratch.size() * sizeof(float)),
                           depth_scratch.data());
      buildDepthPyramid(depth_scratch, res, res, p.first_row, pyramid);
      stats.triangles_hidden += keepUnhidden(p.rest, p.face, face_chunks);
      if (round == kOcclusionRounds) {
        p.rest.clear();
        p.next.swap(face_chunks);
      } else {
        splitNearest(chunks, face_chunks, p.face.eye, occlusionFirstTriangles(chunks, face_chunks),
                     p.next, p.rest);
      }
    }
    for (PendingFace& p : pending_faces) {
      if (p.next.empty()) continue;
      if (p.sample != current) {
        useSample(batch[p.sample]);
        current = p.sample;
      }
      useLayer(p.layer, p.first_row);
      glProgramUniformMatrix3fv(program, 1, 1, GL_TRUE, p.view_from_world.data());
      drawForSample(batch, p.sample, p.next, stats);
    }
    std::erase_if(pending_faces, [](const PendingFace& p) { return p.rest.empty(); });
  }
}

}  // namespace svit::gl
