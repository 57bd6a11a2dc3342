//! GLSL 3.30 core shaders: the studio lighting (key with a shadow map, fill, rim,
//! sky/ground ambient), the mesh, the particle sphere impostors, the ground with its
//! soft contact shadow, and the depth-only shadow passes.

/// Lighting shared by the mesh, point and ground fragment shaders.
const LIGHTING: &str = r#"
uniform vec3 u_eye;
uniform vec3 u_key;
uniform vec3 u_fill;
uniform vec3 u_rim;
uniform float u_key_strength;
uniform sampler2DShadow u_shadow;
uniform float u_shadow_texel;
uniform mat4 u_light_view_proj;
uniform float u_bias; // depth-comparison bias (shadow-map depth units)

// Fraction of the key light that reaches p: percentage-closer filtering on the shadow
// map, `taps`² bilinear comparisons `spread` texels apart.
float key_visibility(vec3 p, int taps, float spread) {
    vec4 l = u_light_view_proj * vec4(p, 1.0);
    vec3 s = l.xyz / l.w * 0.5 + 0.5;
    if (s.z >= 1.0 || any(lessThan(s.xy, vec2(0.0))) || any(greaterThan(s.xy, vec2(1.0))))
        return 1.0;
    float sum = 0.0;
    float h = 0.5 * float(taps - 1);
    for (int i = 0; i < taps; ++i)
        for (int j = 0; j < taps; ++j) {
            vec2 o = (vec2(float(i), float(j)) - h) * spread * u_shadow_texel;
            sum += texture(u_shadow, vec3(s.xy + o, s.z - u_bias));
        }
    return sum / float(taps * taps);
}

// Key (Lambert + Blinn–Phong gloss), fill, rim and a sky/ground ambient.
// material: 0 surface, 1 crack face, 2 collider.
vec3 studio(vec3 p, vec3 n, vec3 albedo, float material, float visibility) {
    vec3 v = normalize(u_eye - p);
    if (dot(n, v) < 0.0) n = -n;
    float key = max(dot(n, u_key), 0.0) * visibility * u_key_strength;
    float fill = max(dot(n, u_fill), 0.0) * 0.35;
    float rim = max(dot(n, u_rim), 0.0) * pow(1.0 - max(dot(n, v), 0.0), 2.0) * 0.9;
    vec3 ambient = mix(vec3(0.10, 0.09, 0.08), vec3(0.16, 0.18, 0.22), 0.5 + 0.5 * n.y);
    float gloss = material > 1.5 ? 0.6 : (material > 0.5 ? 0.0 : 0.12);
    float power = material > 1.5 ? 80.0 : 32.0;
    vec3 h = normalize(u_key + v);
    float spec = gloss * pow(max(dot(n, h), 0.0), power) * visibility * u_key_strength;
    return albedo * (ambient + vec3(1.0, 0.97, 0.92) * key + vec3(0.85, 0.9, 1.0) * fill)
        + vec3(rim + spec);
}
"#;

/// Mesh vertex shader.
pub const MESH_VERTEX: &str = r#"#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec3 a_color;
layout(location = 3) in float a_material;
uniform mat4 u_view_proj;
out vec3 v_position;
out vec3 v_normal;
out vec3 v_color;
out float v_material;
void main() {
    v_position = a_position;
    v_normal = a_normal;
    v_color = a_color;
    v_material = a_material;
    gl_Position = u_view_proj * vec4(a_position, 1.0);
}
"#;

/// Mesh fragment shader (header; `LIGHTING` and the body follow).
pub fn mesh_fragment() -> String {
    format!(
        "#version 330 core\n{LIGHTING}{}",
        r#"
in vec3 v_position;
in vec3 v_normal;
in vec3 v_color;
in float v_material;
out vec4 o_color;
void main() {
    vec3 n = normalize(v_normal);
    float vis = key_visibility(v_position, 1, 1.0);
    o_color = vec4(studio(v_position, n, v_color, v_material, vis), 1.0);
}
"#
    )
}

/// Point (sphere impostor) vertex shader: one vertex a particle, sized in pixels from
/// its world radius.
pub const POINT_VERTEX: &str = r#"#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in float a_radius;
layout(location = 2) in vec3 a_color;
uniform mat4 u_view_proj;
uniform float u_pixels_per_unit; // projection[1][1] * viewport height / 2 (or ortho scale)
uniform float u_perspective;     // 1: divide by w (camera), 0: orthographic (shadow)
out vec3 v_center;
out float v_radius;
out vec3 v_color;
void main() {
    vec4 c = u_view_proj * vec4(a_position, 1.0);
    gl_Position = c;
    float w = mix(1.0, c.w, u_perspective);
    gl_PointSize = max(2.0 * a_radius * u_pixels_per_unit / w, 1.0);
    v_center = a_position;
    v_radius = a_radius;
    v_color = a_color;
}
"#;

/// Point fragment shader: a lit sphere inside the point's disc, nothing outside.
pub fn point_fragment() -> String {
    format!(
        "#version 330 core\n{LIGHTING}{}",
        r#"
uniform vec3 u_cam_right;
uniform vec3 u_cam_up;
in vec3 v_center;
in float v_radius;
in vec3 v_color;
out vec4 o_color;
void main() {
    vec2 d = gl_PointCoord * 2.0 - 1.0;
    d.y = -d.y;
    float r2 = dot(d, d);
    if (r2 > 1.0) discard;
    vec3 back = cross(u_cam_right, u_cam_up);
    vec3 n = d.x * u_cam_right + d.y * u_cam_up + sqrt(1.0 - r2) * back;
    vec3 p = v_center + n * v_radius;
    float vis = key_visibility(p, 1, 1.0);
    o_color = vec4(studio(p, n, v_color, 0.0, vis), 1.0);
}
"#
    )
}

/// Ground vertex shader: a square of half-size `u_extent` at height `u_height` centred
/// under the scene, made from the vertex id (no buffer).
pub const GROUND_VERTEX: &str = r#"#version 330 core
uniform mat4 u_view_proj;
uniform vec3 u_center;
uniform float u_extent;
out vec3 v_position;
void main() {
    vec2 corner = vec2(float((gl_VertexID & 1) * 2 - 1), float((gl_VertexID >> 1) * 2 - 1));
    v_position = vec3(u_center.x + corner.x * u_extent, u_center.y, u_center.z + corner.y * u_extent);
    gl_Position = u_view_proj * vec4(v_position, 1.0);
}
"#;

/// Ground fragment shader: a matte floor fading into the backdrop, with a wide PCF
/// kernel for a soft contact shadow.
pub fn ground_fragment() -> String {
    format!(
        "#version 330 core\n{LIGHTING}{}",
        r#"
uniform vec3 u_center;
uniform float u_fade_start;
uniform float u_fade_end;
uniform vec3 u_background;
in vec3 v_position;
out vec4 o_color;
void main() {
    float vis = key_visibility(v_position, 2, 2.0);
    vec3 albedo = vec3(0.55, 0.55, 0.56);
    vec3 c = studio(v_position, vec3(0.0, 1.0, 0.0), albedo, 0.0, vis);
    float r = length(v_position.xz - u_center.xz);
    o_color = vec4(mix(c, u_background, smoothstep(u_fade_start, u_fade_end, r)), 1.0);
}
"#
    )
}

/// Depth-only vertex shader for meshes in the shadow pass.
pub const SHADOW_MESH_VERTEX: &str = r#"#version 330 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_view_proj;
void main() {
    gl_Position = u_view_proj * vec4(a_position, 1.0);
}
"#;

/// Depth-only fragment shader for meshes.
pub const SHADOW_MESH_FRAGMENT: &str = r#"#version 330 core
void main() {}
"#;

/// Depth-only fragment shader for points: the disc only.
pub const SHADOW_POINT_FRAGMENT: &str = r#"#version 330 core
void main() {
    vec2 d = gl_PointCoord * 2.0 - 1.0;
    if (dot(d, d) > 1.0) discard;
}
"#;
