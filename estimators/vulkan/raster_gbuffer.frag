// Raster G-buffer, fragment stage: the rasteriser chose the visible triangle; the attributes come
// from intersecting this pixel's camera ray with it, exactly as scenes/gbuffer.cpp derives them
// from Embree's hit (barycentric P, Ng from the corners, interpolated N, two-sided flip).
#version 450

layout(std430, set = 0, binding = 0) readonly buffer Positions { float positions[]; };
layout(std430, set = 0, binding = 1) readonly buffer Indices { uint indices[]; };
layout(std430, set = 0, binding = 2) readonly buffer Normals { float normals[]; };

layout(push_constant) uniform Camera {
  vec4 eye_near;
  vec4 forward_tan;
  vec4 right_width;
  vec4 up_height;
  int object_id;
  uint has_normals;
} cam;

layout(location = 0) flat in uint triangle;
layout(location = 1) in vec3 world;

layout(location = 0) out float out_coverage;
layout(location = 1) out float out_depth;
layout(location = 2) out vec4 out_position;
layout(location = 3) out vec4 out_normal;
layout(location = 4) out vec4 out_geometric_normal;
layout(location = 5) out float out_object_id;

vec3 fetch(uint v) { return vec3(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]); }
vec3 fetch_normal(uint v) { return vec3(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]); }

void main() {
  const uint i0 = indices[3 * triangle], i1 = indices[3 * triangle + 1],
             i2 = indices[3 * triangle + 2];
  const vec3 p0 = fetch(i0), p1 = fetch(i1), p2 = fetch(i2);
  const vec3 eye = cam.eye_near.xyz;

  // Camera::direction for this pixel centre (gl_FragCoord.xy = (i + 0.5, j + 0.5)).
  const float width = cam.right_width.w, height = cam.up_height.w;
  const float tan_y = cam.forward_tan.w;
  const float x = (2.0 * gl_FragCoord.x / width - 1.0) * tan_y * (width / height);
  const float y = (1.0 - 2.0 * gl_FragCoord.y / height) * tan_y;
  const vec3 dir = normalize(cam.forward_tan.xyz + x * cam.right_width.xyz + y * cam.up_height.xyz);

  // Moller-Trumbore: P = (1 - u - v) p0 + u p1 + v p2 on the ray, Embree's (u, v) convention.
  const vec3 e1 = p1 - p0, e2 = p2 - p0, s = eye - p0;
  const vec3 pv = cross(dir, e2);
  const float det = dot(e1, pv);
  float u = dot(s, pv) / det;
  float v = dot(dir, cross(s, e1)) / det;
  // A nearly edge-on triangle makes the ray solution ill-conditioned; there, fall back to the
  // barycentrics of the interpolated world position (the pixel centre is inside the triangle).
  const float slack = 1e-3;
  if (!(u >= -slack && v >= -slack && u + v <= 1.0 + slack)) {
    const vec3 n = cross(e1, e2);
    const float nn = dot(n, n);
    u = dot(cross(world - p0, e2), n) / nn;
    v = dot(cross(e1, world - p0), n) / nn;
  }
  u = clamp(u, 0.0, 1.0);
  v = clamp(v, 0.0, 1.0 - u);
  const float w = 1.0 - u - v;

  const vec3 p = w * p0 + u * p1 + v * p2;
  vec3 ng = normalize(cross(e1, e2));
  vec3 ns = ng;
  if (cam.has_normals != 0u) {
    const vec3 sn = w * fetch_normal(i0) + u * fetch_normal(i1) + v * fetch_normal(i2);
    const float len = length(sn);
    if (len > 1e-12 && !isinf(len) && !isnan(len)) ns = sn / len;
  }
  if (dot(ng, dir) > 0.0) {  // two-sided: face the viewer
    ng = -ng;
    ns = -ns;
  }
  out_coverage = 1.0;
  out_depth = dot(p - eye, cam.forward_tan.xyz);
  out_position = vec4(p, 1.0);
  out_normal = vec4(ns, 0.0);
  out_geometric_normal = vec4(ng, 0.0);
  out_object_id = float(cam.object_id);
}
