// Canvas program: Kubelka-Munk mixing of pigment concentrations per band, then impasto lighting.
//
// One file holds both stages; the loader prepends "#version 330 core" and defines VERTEX_SHADER or
// FRAGMENT_SHADER, plus N_GROUPS (bands / 4), MAX_PIGMENTS and N_LAYERS (concentration layers).
// Frame: canvas metres, x right, y up, z out of the canvas towards the viewer.

#ifdef VERTEX_SHADER
in vec2 in_pos_m;        // a canvas corner, metres
uniform mat3 u_view;     // canvas metres -> clip space
out vec2 v_pos_m;

void main() {
    v_pos_m = in_pos_m;
    gl_Position = vec4((u_view * vec3(in_pos_m, 1.0)).xy, 0.0, 1.0);
}
#endif

#ifdef FRAGMENT_SHADER
uniform sampler2DArray u_concentration;   // layer l, channel j: pigment 4 l + j volume fraction
uniform sampler2D u_surface;              // r: paint height (m), g: wetness [0, 1]
uniform sampler2D u_tooth;                // r: the canvas surface's tooth height (m), zero-mean
uniform float u_tooth_relief_m;           // the tooth's peak-to-valley height (0: smooth), m
uniform vec2 u_canvas_size_m;
uniform vec2 u_texel_m;                   // texel size, metres
uniform int u_pigment_count;
uniform vec4 u_k[MAX_PIGMENTS * N_GROUPS]; // absorption K per band, 1/m, pigment-major
uniform vec4 u_s[MAX_PIGMENTS * N_GROUPS]; // scattering S per band, 1/m
uniform vec4 u_ground[N_GROUPS];          // ground reflectance per band
uniform vec4 u_band_r[N_GROUPS];          // band reflectance -> linear R, G, B weights
uniform vec4 u_band_g[N_GROUPS];
uniform vec4 u_band_b[N_GROUPS];
uniform bool u_lighting;
uniform vec3 u_light_dir;                 // unit vector towards the light
uniform float u_ambient;                  // share of light that ignores the relief, [0, 1]
uniform float u_relief;                   // height exaggeration (1 = true relief)
uniform float u_specular;                 // specular strength of fully wet paint
uniform float u_shininess;                // Blinn-Phong exponent
in vec2 v_pos_m;
out vec4 f_color;

// Kubelka-Munk reflectance of a layer (K, S per band, thickness X) over the ground, with
// t = tanh(beta X) / beta computed without overflow and accurately near beta X = 0.
vec4 km_layer(vec4 k, vec4 s, float thickness, vec4 ground) {
    vec4 beta = sqrt(k * (k + 2.0 * s));
    vec4 x = beta * thickness;
    vec4 e = exp(-2.0 * min(x, vec4(20.0)));
    vec4 t_thick = (1.0 - e) / ((1.0 + e) * max(beta, vec4(1e-30)));
    vec4 t_thin = thickness * (1.0 - x * x / 3.0);
    vec4 t = mix(t_thick, t_thin, lessThan(x, vec4(1e-3)));
    vec4 num = t * (s - ground * (s + k)) + ground;
    vec4 den = t * (s + k - ground * s) + 1.0;
    return num / den;
}

vec3 paint_colour(vec2 uv, float thickness) {
    vec4 k[N_GROUPS];
    vec4 s[N_GROUPS];
    for (int g = 0; g < N_GROUPS; ++g) {
        k[g] = vec4(0.0);
        s[g] = vec4(0.0);
    }
    for (int layer = 0; layer < N_LAYERS; ++layer) {
        if (4 * layer >= u_pigment_count) break;
        vec4 c = texture(u_concentration, vec3(uv, float(layer)));
        for (int j = 0; j < 4; ++j) {
            int p = 4 * layer + j;
            if (p >= u_pigment_count) break;
            if (c[j] <= 0.0) continue;
            for (int g = 0; g < N_GROUPS; ++g) {
                k[g] += c[j] * u_k[p * N_GROUPS + g];
                s[g] += c[j] * u_s[p * N_GROUPS + g];
            }
        }
    }
    vec3 rgb = vec3(0.0);
    for (int g = 0; g < N_GROUPS; ++g) {
        vec4 r = km_layer(k[g], s[g], thickness, u_ground[g]);
        rgb += vec3(dot(r, u_band_r[g]), dot(r, u_band_g[g]), dot(r, u_band_b[g]));
    }
    return rgb;
}

// Height of the lit surface: the paint over the canvas's tooth, the tooth fading out under paint
// as thick as its relief (a thick layer hides it; bare and thinly painted tooth shows).
float lit_height(vec2 uv) {
    float paint = texture(u_surface, uv).r;
    if (u_tooth_relief_m <= 0.0) return paint;
    float cover = clamp(1.0 - max(paint, 0.0) / u_tooth_relief_m, 0.0, 1.0);
    return paint + cover * texture(u_tooth, uv).r;
}

vec3 light(vec3 albedo, vec2 uv, float wetness) {
    vec2 du = vec2(1.0, 0.0) / vec2(textureSize(u_surface, 0));
    vec2 dv = vec2(0.0, 1.0) / vec2(textureSize(u_surface, 0));
    float dhdx = (lit_height(uv + du) - lit_height(uv - du)) / (2.0 * u_texel_m.x);
    float dhdy = (lit_height(uv + dv) - lit_height(uv - dv)) / (2.0 * u_texel_m.y);
    vec3 n = normalize(vec3(-u_relief * dhdx, -u_relief * dhdy, 1.0));
    // Diffuse relative to a flat surface: flat paint shows its Kubelka-Munk colour unchanged.
    float diffuse = u_ambient + (1.0 - u_ambient) * max(dot(n, u_light_dir), 0.0)
                    / max(u_light_dir.z, 0.05);
    vec3 h = normalize(u_light_dir + vec3(0.0, 0.0, 1.0));
    float spec = u_specular * wetness * pow(max(dot(n, h), 0.0), u_shininess);
    return albedo * diffuse + vec3(spec);
}

void main() {
    vec2 uv = v_pos_m / u_canvas_size_m;
    vec2 surface = texture(u_surface, uv).rg;
    vec3 rgb = paint_colour(uv, max(surface.r, 0.0));
    if (u_lighting) {
        rgb = light(rgb, uv, surface.g);
    }
    f_color = vec4(rgb, 1.0);
}
#endif
