// Picture program: the cached lit canvas (linear RGB, one texel per canvas texel) drawn in canvas
// metres, bilinearly filtered.
//
// The loader prepends "#version 330 core" and defines VERTEX_SHADER or FRAGMENT_SHADER.

#ifdef VERTEX_SHADER
in vec2 in_pos_m;          // vertex, canvas metres
uniform mat3 u_view;       // canvas metres -> clip space
uniform vec2 u_canvas_size_m;
out vec2 v_uv;

void main() {
    v_uv = in_pos_m / u_canvas_size_m;
    gl_Position = vec4((u_view * vec3(in_pos_m, 1.0)).xy, 0.0, 1.0);
}
#endif

#ifdef FRAGMENT_SHADER
uniform sampler2D u_picture;
in vec2 v_uv;
out vec4 f_color;

void main() {
    f_color = vec4(texture(u_picture, v_uv).rgb, 1.0);
}
#endif
