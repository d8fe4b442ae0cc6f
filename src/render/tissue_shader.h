#pragma once
/// The GLSL of MeshRenderer: Blinn-Phong lit by the laparoscope's light (at the eye, inverse-
/// square fall-off, a spot cone around the optical axis) and the procedural tissue textures
/// (docs/rendering.md, "Materials and lighting"). Textures are computed per fragment from a
/// point of the tissue's own space: no image assets, nothing random between runs.

namespace viscera::render {

inline constexpr char kTissueVertexShader[] = R"(#version 330 core
uniform mat4 u_view;
uniform mat4 u_projection;
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec3 a_texture;
out vec3 v_position;  // view space
out vec3 v_normal;    // view space
out vec3 v_texture;   // the tissue's own space (m)
#ifdef SEROSA_PER_VERTEX
// the serosa's noises at the vertex: the vessels' reach, the wet film, the bands' waviness
out vec3 v_serosa;
#endif
#ifdef SEROSA_ATTRIBUTE
// the same noises given with each vertex, computed once by this shader (a skin whose texture
// points never change: the viewer page's parametric skin)
layout(location = 3) in vec3 a_serosa;
#endif
void main() {
  vec4 p = u_view * vec4(a_position, 1.0);
  v_position = p.xyz;
  v_normal = mat3(u_view) * a_normal;  // u_view is rigid: no inverse transpose needed
  v_texture = a_texture;
#if defined(SEROSA_ATTRIBUTE)
  v_serosa = a_serosa;
#elif defined(SEROSA_PER_VERTEX)
  v_serosa = vec3(SerosaReach(a_texture), SerosaFilm(a_texture), SerosaWave(a_texture));
#endif
  gl_Position = u_projection * p;
}
)";

// Light at the eye: the light and view directions coincide, so the half vector is the view
// direction and both lobes are powers of n.v. A sharp lobe (u_shininess) and a broad one
// (u_sheen) together give the wet look of mucosa. The light falls off as 1 / (1 + (d/range)^2)
// with the distance d from the scope tip (inverse square beyond `range`, finite at the lens),
// times the spot cone. Vessels are where a smooth value noise (or a wavy band) crosses zero.
// Compiled once per Pattern, after "#version 330 core" and "#define PATTERN <n>": llvmpipe runs
// both sides of a branch on a uniform, so one program with every pattern would cost every
// fragment all of them.
//
// The noise, a line and the serosa's noises: before kTissueFragmentShader, and before the
// vertex shader's body when SEROSA_PER_VERTEX is defined (after "#version 330 core").
inline constexpr char kTissueNoise[] = R"(
float Hash(vec3 p) {
  p = fract(p * 0.3183099 + vec3(0.71, 0.113, 0.419));
  p *= 17.0;
  return fract(p.x * p.y * p.z * (p.x + p.y + p.z));
}

// Value noise in [-1, 1], C1, one lattice cell per unit.
float Noise(vec3 p) {
  vec3 i = floor(p);
  vec3 f = p - i;
  vec3 u = f * f * (3.0 - 2.0 * f);
  float a = mix(Hash(i), Hash(i + vec3(1.0, 0.0, 0.0)), u.x);
  float b = mix(Hash(i + vec3(0.0, 1.0, 0.0)), Hash(i + vec3(1.0, 1.0, 0.0)), u.x);
  float c = mix(Hash(i + vec3(0.0, 0.0, 1.0)), Hash(i + vec3(1.0, 0.0, 1.0)), u.x);
  float d = mix(Hash(i + vec3(0.0, 1.0, 1.0)), Hash(i + vec3(1.0, 1.0, 1.0)), u.x);
  return 2.0 * mix(mix(a, b, u.y), mix(c, d, u.y), u.z) - 1.0;
}

// 1 on the zero set of `n`, 0 beyond `width` of it.
float Line(float n, float width) { return 1.0 - smoothstep(0.0, width, abs(n)); }

// The serosa's slowly varying terms at p = (along the bowel, around it), m: how far round the
// tube a vessel reaches (0 to 1) and the wet film's patches (-1 to 1).
float SerosaReach(vec3 p) { return smoothstep(0.0, 0.5, Noise(vec3(p.x * 140.0, p.yz * 25.0))); }
float SerosaFilm(vec3 p) { return Noise(p * 160.0 + 3.7); }
// The bands' waviness and the mottle (-1 to 1).
float SerosaWave(vec3 p) { return Noise(p * 90.0); }
)";

// After "#version 330 core", "#define PATTERN <n>" (and "#define SEROSA_PER_VERTEX": the serosa's
// noises, reach, film and wave, computed per vertex, or given with it by SEROSA_ATTRIBUTE, and
// interpolated), kTissueNoise (and
// "#define INTEGER_EXPONENTS" with PowShininess and PowSheenShininess: the material's whole
// exponents as products, IntegerPowerSource).
inline constexpr char kTissueFragmentShader[] = R"(
uniform vec3 u_albedo;
uniform float u_ambient;
uniform float u_specular;
uniform float u_shininess;
uniform float u_sheen;
uniform float u_sheen_shininess;
uniform float u_metallic;
uniform float u_light_range;
uniform float u_opacity;
uniform vec3 u_vessel;
uniform vec2 u_spot;       // cosines of the cone's inner and outer half angles; x <= y: no cone
in vec3 v_position;
in vec3 v_normal;
in vec3 v_texture;
#ifdef SEROSA_PER_VERTEX
in vec3 v_serosa;
#endif
out vec4 frag_colour;

void main() {
  vec3 to_eye = normalize(-v_position);
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;
  float diffuse = max(dot(n, to_eye), 0.0);
  float light = 1.0;
  if (u_light_range > 0.0) {
    float d = length(v_position) / u_light_range;
    light = 1.0 / (1.0 + d * d);
  }
  if (u_spot.x > u_spot.y) light *= smoothstep(u_spot.y, u_spot.x, to_eye.z);

  vec3 albedo = u_albedo;
  float specular = u_specular;
  float opacity = u_opacity;
  vec3 p = v_texture;
#if PATTERN == 1
    // parietal peritoneum: a faint mottle, branching vessels (a warped noise's zero set) and
    // finer capillaries
    float mottle = Noise(p * 45.0);
    vec3 q = p * 28.0 + 0.7 * vec3(mottle, Noise(p * 45.0 + 11.3), 0.0);
    float vessels = 0.6 * Line(Noise(q), 0.05) + 0.3 * Line(Noise(p * 95.0 + 5.3), 0.04);
    albedo *= 1.0 + 0.10 * mottle;
    albedo = mix(albedo, u_vessel, vessels);
    specular *= 0.7 + 0.5 * mottle;
#elif PATTERN == 2
    // serosa: p = (along the bowel, around it), m. Vasa recta: bands around the tube every
    // 7 mm, wavy, each fading out part of the way round; a patchy wet film
#ifdef SEROSA_PER_VERTEX
    float reach = v_serosa.x, film = v_serosa.y, wave = v_serosa.z;
#else
    float reach = SerosaReach(p), film = SerosaFilm(p), wave = SerosaWave(p);
#endif
    float band = Line(sin(3.14159 * (p.x / 0.007 + 0.35 * wave)), 0.22);
    albedo *= 1.0 + 0.08 * wave;
    albedo = mix(albedo, u_vessel, 0.7 * band * reach);
    specular *= 0.6 + 0.6 * film;
#elif PATTERN == 3
    // mesentery: p = (along the bowel, from the root toward it), m. Straight vessels from the
    // root, every 2 cm, wavy; arcades joining them near the bowel; fat lobules
    float wave = Noise(p * 40.0);
    float radial = Line(sin(3.14159 * (p.x / 0.02 + 0.5 * wave)), 0.10);
    float arcade = Line(sin(3.14159 * (p.y / 0.05 + 0.8 * Noise(p * 25.0 + 7.1))), 0.12) *
                   smoothstep(0.05, 0.10, p.y);
    float vessels = min(radial + arcade, 1.0);
    albedo *= 1.0 + 0.12 * wave;
    albedo = mix(albedo, u_vessel, vessels);
    opacity = mix(opacity, min(1.0, 2.4 * opacity), vessels);
#endif

#ifdef INTEGER_EXPONENTS
  float highlight = specular * PowShininess(diffuse) + u_sheen * PowSheenShininess(diffuse);
#else
  float highlight = specular * pow(diffuse, u_shininess) + u_sheen * pow(diffuse, u_sheen_shininess);
#endif
  vec3 highlight_colour = mix(vec3(1.0), albedo, u_metallic);
  vec3 colour = albedo * (u_ambient + (1.0 - u_ambient) * diffuse * light) +
                highlight_colour * (highlight * light);
  frag_colour = vec4(min(colour, vec3(1.0)), opacity);
}
)";

}  // namespace viscera::render
