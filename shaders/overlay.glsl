// Overlay program: flat-coloured triangles in canvas metres (brush outline, force arrows).
//
// The loader prepends "#version 330 core" and defines VERTEX_SHADER or FRAGMENT_SHADER.

#ifdef VERTEX_SHADER
in vec2 in_pos_m;        // vertex, canvas metres
uniform mat3 u_view;     // canvas metres -> clip space

void main() {
    gl_Position = vec4((u_view * vec3(in_pos_m, 1.0)).xy, 0.0, 1.0);
}
#endif

#ifdef FRAGMENT_SHADER
uniform vec4 u_color;    // linear RGB and opacity
out vec4 f_color;

void main() {
    f_color = u_color;
}
#endif
