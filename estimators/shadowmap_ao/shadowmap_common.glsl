// shadowmap-ao: what the depth and accumulation passes share (GPU Gems ch. 17 §17.3).
// The light's orthographic frame: u, v span the map, d points towards the light. The map covers the
// scene's bounding sphere (centre c, radius R): x = (p - c)·u / R and y = (p - c)·v / R in [-1, 1],
// depth = 1/2 - (p - c)·d / (2R) in [0, 1], 0 nearest the light.
struct Light {
  vec4 u, v, d;
};

layout(std430, set = 0, binding = 1) readonly buffer Lights { Light lights[]; };

vec3 light_space(vec3 p, vec4 centre_radius, Light l) {
  const vec3 q = p - centre_radius.xyz;
  const float r = centre_radius.w;
  return vec3(dot(q, l.u.xyz) / r, dot(q, l.v.xyz) / r, 0.5 - dot(q, l.d.xyz) / (2.0 * r));
}
