;;;; model-shaders.lisp -- the GLSL 330 core programs that draw imported
;;;; models: linear-blend skinning in the vertex shader (four palette entries
;;;; and weights a vertex), or vertices the CPU skinned; a diffuse texture
;;;; times a vertex or material colour, lit as shaders.lisp lights bodies.

(in-package #:player.render)

;;; Both programs share one fragment shader, so the GPU and the CPU paths
;;; differ only in who blends the palette: the same picture either way.  The
;;; lighting is the mesh fragment shader's (see the cost notes at the top of
;;; shaders.lisp), with the albedo a texel times a tint; an untextured mesh
;;; samples a 1x1 white texture instead of branching per pixel.  Palette
;;; slots arrive as floats (exact below 2^24), which every GL 3.3 converts
;;; from unsigned shorts; the blended matrix costs four fetches per vertex,
;;; nothing per pixel.

(defconstant +palette-size+ 128
  "Palette matrices the skinning vertex shader holds; a skin with more is skinned on the CPU.")

(defparameter *skinned-vertex-shader*
  (format nil "#version 330 core
layout(location = 0) in vec3 position;   // the mesh's own space
layout(location = 1) in vec3 normal;
layout(location = 2) in vec4 colour;     // vertex or material colour, gamma-encoded
layout(location = 3) in vec2 uv;
layout(location = 4) in vec4 slots;      // four palette entries...
layout(location = 5) in vec4 weights;    // ...and their weights, summing to 1
uniform mat4 view_projection;
uniform mat4 palette[~D];
out vec3 world_position;
out vec3 world_normal;
out vec3 tint;               // linear
out vec2 texture_uv;
void main() {
  mat4 blend = palette[int(slots.x)] * weights.x + palette[int(slots.y)] * weights.y
             + palette[int(slots.z)] * weights.z + palette[int(slots.w)] * weights.w;
  vec4 p = blend * vec4(position, 1.0);
  world_position = p.xyz;
  world_normal = mat3(blend) * normal;
  tint = colour.rgb * colour.rgb;
  texture_uv = uv;
  gl_Position = view_projection * p;
}" +palette-size+)
  "Vertex shader for a skin: linear-blend skinning by the palette, normals by the blended linear part.")

(defparameter *posed-model-vertex-shader*
  "#version 330 core
layout(location = 0) in vec3 position;   // world space: the CPU skinned it
layout(location = 1) in vec3 normal;
layout(location = 2) in vec4 colour;
layout(location = 3) in vec2 uv;
uniform mat4 view_projection;
out vec3 world_position;
out vec3 world_normal;
out vec3 tint;
out vec2 texture_uv;
void main() {
  world_position = position;
  world_normal = normal;
  tint = colour.rgb * colour.rgb;
  texture_uv = uv;
  gl_Position = view_projection * vec4(position, 1.0);
}"
  "Vertex shader for a skin posed on the CPU (SKIN-VERTICES): the fallback path.")

(defparameter *model-fragment-shader*
  (concatenate 'string "#version 330 core
in vec3 world_position;
in vec3 world_normal;
in vec3 tint;
in vec2 texture_uv;
uniform sampler2D diffuse;
uniform bool textured;       // false: no texture to sample (llvmpipe's filtering costs)
out vec4 fragment;
" *lighting-glsl* "void main() {
  vec3 texel = textured ? texture(diffuse, texture_uv).rgb : vec3(1.0);
  fragment = vec4(lit_surface(tint * texel * texel, world_position, world_normal), 1.0);
}")
  "Fragment shader for models: the diffuse texel times the tint, lit as bodies are.")

(defparameter *model-colour* '(0.78 0.74 0.68)
  "The material colour (R G B) of a mesh with neither texture nor vertex colours.")
