// shadowmap-ao, depth pass, fragment stage: the nearest depth (the depth test keeps it) into the R32F
// atlas. Only depth is written; it goes to a colour attachment because the shared layer's depth
// attachment is not stored (estimators/vulkan/vk_pipelines.h).
#version 450

layout(location = 0) out float depth;

void main() {
  depth = gl_FragCoord.z;
}
