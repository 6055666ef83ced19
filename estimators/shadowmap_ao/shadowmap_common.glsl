// shadowmap-ao: what the depth and accumulation passes share (GPU Gems ch. 17 §17.3).
// The light's orthographic frame: u, v span the map, d points towards the light. Depth covers the
// scene's bounding sphere (centre c, radius R), so every occluder along the light is in the map:
// depth = 1/2 - (p - c)·d / (2R) in [0, 1], 0 nearest the light. Laterally the map covers
// fit = (centre along u, centre along v, 1 / half-width along u, 1 / half-width along v):
// x = ((p - c)·u - fit.x) fit.z and y = ((p - c)·v - fit.y) fit.w in [-1, 1]; fit = scene: the
// sphere (0, 0, 1/R, 1/R); fit = receivers: the receivers' extent as this light sees them (like a
// cascaded shadow map fitted to the view), so the texels go where the receivers are. d.w = one
// texel's width over the sphere fit's (max(half-widths) / R): the bias, given in texels, scales
// with it.
struct Light {
  vec4 u, v, d, fit;
};

layout(std430, set = 0, binding = 1) readonly buffer Lights { Light lights[]; };

vec3 light_space(vec3 p, vec4 centre_radius, Light l) {
  const vec3 q = p - centre_radius.xyz;
  const float r = centre_radius.w;
  return vec3((dot(q, l.u.xyz) - l.fit.x) * l.fit.z, (dot(q, l.v.xyz) - l.fit.y) * l.fit.w,
              0.5 - dot(q, l.d.xyz) / (2.0 * r));
}
