#version 450
// Reinhard's simple operator Ld = L / (1 + L) with L = exposure * Lw (seed 003 eq. 4.2; the
// exposure is key / Lavg or 2^ev, from the luminance pass), written in GLSL 450 to show both
// shader languages in one pipeline. Lw is the tone value: the largest channel, or luminance
// when the luminance pass says so (lib/luminance.wgsl).

layout(location = 0) in vec2 uv;
layout(location = 0) out vec4 color;

layout(set = 2, binding = 0) uniform texture2D hdr;
layout(set = 2, binding = 1) readonly buffer Luminance {
    float log_average;
    float white;
    float exposure;
    float covered;
    float by_luminance;
} lum;

void main() {
    vec3 c = texelFetch(hdr, ivec2(gl_FragCoord.xy), 0).rgb;
    float lw = lum.by_luminance > 0.5 ? dot(c, vec3(0.2126, 0.7152, 0.0722)) : max(c.r, max(c.g, c.b));
    if (!(lw > 0.0)) {
        color = vec4(0.0, 0.0, 0.0, 1.0);
        return;
    }
    float l = lw * lum.exposure;
    float ld = l / (1.0 + l);
    color = vec4(clamp(c * (ld / lw), 0.0, 1.0), 1.0);
}
