// Raster G-buffer, vertex stage: the pinhole camera of CONTRACT §3 (scenes/camera.h) as a clip
// transform. Triangles are drawn non-indexed: vertex 3t + k is corner k of triangle t, fetched
// through the index buffer, so the triangle index reaches the fragment stage as a flat varying.
#version 450

layout(std430, set = 0, binding = 0) readonly buffer Positions { float positions[]; };
layout(std430, set = 0, binding = 1) readonly buffer Indices { uint indices[]; };

layout(push_constant) uniform Camera {
  vec4 eye_near;      // eye, near-plane distance
  vec4 forward_tan;   // unit forward, tan(fov_y / 2)
  vec4 right_width;   // unit right, image width in pixels
  vec4 up_height;     // unit up, image height in pixels
  int object_id;
  uint has_normals;
} cam;

layout(location = 0) flat out uint triangle;
layout(location = 1) out vec3 world;

void main() {
  const uint v = indices[gl_VertexIndex];
  const vec3 p = vec3(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
  const vec3 d = p - cam.eye_near.xyz;
  const float aspect = cam.right_width.w / cam.up_height.w;
  const float tan_y = cam.forward_tan.w;
  // Camera::direction maps pixel centre (i + 0.5, j + 0.5) to x = ndc_x * tan * aspect and
  // y = -ndc_y * tan (row 0 at the top, Vulkan's NDC y points down): divide the view-space point by
  // its depth the same way. Reversed Z with an infinite far plane: depth = near / z.
  const float z = dot(d, cam.forward_tan.xyz);
  gl_Position = vec4(dot(d, cam.right_width.xyz) / (tan_y * aspect),
                     -dot(d, cam.up_height.xyz) / tan_y, cam.eye_near.w, z);
  triangle = uint(gl_VertexIndex) / 3u;
  world = p;
}
