;;;; shaders.lisp -- the renderer's GLSL 330 core programs -- lit meshes (bodies
;;;; and props), the floor, soft contact shadows and the sky -- and the light,
;;;; shadows and floor colour a scene gives them.  renderer.lisp links them in
;;;; whatever context is current.

(in-package #:player.render)

;;; llvmpipe runs these on the CPU, so every fragment instruction counts.
;;; Measured at 640x480: pow() made the lit body cost three times a flat one;
;;; a loop over a uniform count of shadow casters cost 4 ms a frame even with
;;; none; a floor shading each pixel cost 5 ms where an interpolated colour
;;; costs 0.3.  Hence gamma 2.0 rather than 2.2 (decoding is a square, in the
;;; vertex shader; encoding a sqrt), a specular power of 32 by repeated
;;; squaring, light directions normalized on the CPU, a floor lit on the CPU
;;; (its normal is constant) and faded per vertex of a radial grid, and contact
;;; shadows as blurred blobs: a small quad per body, multiplied into what is
;;; under it.  Lights are directional: a key and a fill, each a unit direction
;;; towards the light and a colour already multiplied by its intensity.

(defparameter *mesh-vertex-shader*
  "#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec3 colour;
uniform mat4 view_projection;
out vec3 world_position;
out vec3 world_normal;
out vec3 albedo;             // linear
void main() {
  world_position = position;
  world_normal = normal;
  albedo = colour * colour;
  gl_Position = view_projection * vec4(position, 1.0);
}"
  "Vertex shader for bodies and props, whose vertices SCENE-MESHES poses in world space.")

(defparameter *lighting-glsl*
  "uniform vec3 key_direction;
uniform vec3 key_colour;
uniform vec3 fill_direction;
uniform vec3 fill_colour;
uniform vec3 ambient_colour;
uniform vec3 eye_position;
// A surface of linear ALBEDO lit by the key, fill and ambient lights, gamma-encoded.
vec3 lit_surface(vec3 albedo, vec3 world_position, vec3 world_normal) {
  vec3 n = normalize(world_normal);
  vec3 v = normalize(eye_position - world_position);
  if (dot(n, v) < 0.0) n = -n;   // light the side we see (open discs, thin feathers)
  float key = max(dot(n, key_direction), 0.0);
  float fill = max(dot(n, fill_direction), 0.0);
  // Blinn-Phong highlight from the key light, power 32.
  float s = max(dot(n, normalize(key_direction + v)), 0.0);
  s *= s; s *= s; s *= s; s *= s; s *= s;
  vec3 lit = albedo * (key_colour * key + fill_colour * fill + ambient_colour * (0.75 + 0.25 * n.y))
           + key_colour * (0.2 * s * step(0.0001, key));
  return sqrt(clamp(lit, 0.0, 1.0));
}
"
  "The lighting every lit fragment shader shares (bodies, props, models): its
uniforms and LIT_SURFACE, per-pixel key, fill and ambient light, gamma 2.")

(defparameter *mesh-fragment-shader*
  (concatenate 'string "#version 330 core
in vec3 world_position;
in vec3 world_normal;
in vec3 albedo;
out vec4 fragment;
" *lighting-glsl* "void main() {
  fragment = vec4(lit_surface(albedo, world_position, world_normal), 1.0);
}")
  "Fragment shader for bodies and props: their colour lit (*LIGHTING-GLSL*).")

(defparameter *floor-vertex-shader*
  "#version 330 core
layout(location = 0) in vec3 position;   // a radial grid around the origin, y = 0
uniform mat4 view_projection;
uniform vec3 eye_position;
uniform float floor_height;
uniform float fade_start;    // the floor melts into the horizon from here...
uniform float fade_end;      // ...to here, in metres from the eye
out float far;
void main() {
  vec3 p = vec3(position.x + eye_position.x, floor_height, position.z + eye_position.z);
  far = smoothstep(fade_start, fade_end, length(position.xz));
  gl_Position = view_projection * vec4(p, 1.0);
}"
  "Vertex shader for the floor: a radial grid centred under the eye, faded per vertex.")

(defparameter *floor-fragment-shader*
  "#version 330 core
in float far;
uniform vec3 floor_lit;      // the floor's colour in full light, gamma-encoded
uniform vec3 horizon_colour;
out vec4 fragment;
void main() { fragment = vec4(mix(floor_lit, horizon_colour, far), 1.0); }"
  "Fragment shader for the floor: its lit colour fading into the horizon's.")

(defparameter *shadow-vertex-shader*
  "#version 330 core
uniform mat4 view_projection;
uniform vec4 caster;         // x, z, radius, height of the surface it lies on
out vec2 offset;             // from the centre, in radii
void main() {
  offset = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1)) * 2.0 - 1.0;
  vec3 p = vec3(caster.x + offset.x * caster.z, caster.w, caster.y + offset.y * caster.z);
  gl_Position = view_projection * vec4(p, 1.0);
}"
  "Vertex shader for a contact shadow: a square of two radii lying on a surface,
from gl_VertexID alone (a four-vertex triangle strip).")

(defparameter *shadow-fragment-shader*
  "#version 330 core
in vec2 offset;
uniform float strength;      // how dark the centre is, 0 to 1
out vec4 fragment;
void main() {
  float k = max(1.0 - dot(offset, offset), 0.0);
  fragment = vec4(vec3(1.0 - strength * k * k), 1.0);   // multiplied into the frame
}"
  "Fragment shader for a contact shadow: a soft round blob, darkest in the middle.")

(defparameter *sky-vertex-shader*
  "#version 330 core
uniform mat4 inverse_view_projection;
out vec3 ray;
void main() {
  // One triangle covering the screen, from gl_VertexID alone (no buffers),
  // at the far plane so that it only fills what nothing else covered.
  vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2)) * 2.0 - 1.0;
  vec4 near = inverse_view_projection * vec4(corner, -1.0, 1.0);
  vec4 far = inverse_view_projection * vec4(corner, 1.0, 1.0);
  ray = far.xyz / far.w - near.xyz / near.w;
  gl_Position = vec4(corner, 1.0, 1.0);
}"
  "Vertex shader for the background: a screen-covering triangle carrying view rays.")

(defparameter *sky-fragment-shader*
  "#version 330 core
in vec3 ray;
uniform vec3 horizon_colour;
uniform vec3 zenith_colour;
out vec4 fragment;
void main() {
  float up = ray.y * inversesqrt(dot(ray, ray));
  fragment = vec4(mix(horizon_colour, zenith_colour, smoothstep(0.0, 0.7, up)), 1.0);
}"
  "Fragment shader for the background: a soft vertical gradient by view direction,
the horizon colour where it meets the floor's fade.")

(defparameter *renderer-programs*
  '((:mesh *mesh-vertex-shader* *mesh-fragment-shader*)
    (:floor *floor-vertex-shader* *floor-fragment-shader*)
    (:shadow *shadow-vertex-shader* *shadow-fragment-shader*)
    (:sky *sky-vertex-shader* *sky-fragment-shader*)
    (:fxaa *fxaa-vertex-shader* *fxaa-fragment-shader*))
  "Each program a renderer links: (NAME VERTEX-SOURCE-VARIABLE FRAGMENT-SOURCE-VARIABLE).")

;;;# What the shaders are given

(defparameter *default-lights*
  (list (list (vnormalize (vec3 0.6d0 1.0d0 0.9d0)) '(1.0 0.96 0.9))
        (list (vnormalize (vec3 -0.9d0 0.4d0 0.6d0)) '(0.28 0.32 0.4)))
  "Key and fill, (DIRECTION COLOUR), for a scene without :light objects.")

(defparameter *ambient-colour* '(0.2 0.21 0.24) "Light from everywhere, linear RGB.")

(defun scene-lights (scene focus)
  "The key and fill lights, (DIRECTION COLOUR) each: SCENE's :light objects by
decreasing INTENSITY, directions from FOCUS towards them, colours times
intensities; *DEFAULT-LIGHTS* stand in for missing ones."
  (flet ((property-or (object name default)
           (if (property-type object name nil) (property-value object name) default)))
    (let* ((lights (remove :light (scene-objects scene) :key #'object-kind :test-not #'eq))
           (sorted (stable-sort (copy-list lights) #'> :key (lambda (l) (property-or l 'intensity 1d0))))
           (found (loop for light in sorted
                        for offset = (v- (object-world-position light) focus)
                        when (> (vnorm offset) 1d-6)
                          collect (list (vnormalize offset)
                                        (v* (property-or light 'colour (vec3 1d0 1d0 1d0))
                                            (property-or light 'intensity 1d0))))))
      (list (or (first found) (first *default-lights*))
            (or (second found) (second *default-lights*))))))

(defun lit-floor-colour (colour lights)
  "The gamma-encoded colour (a list) of a floor of COLOUR (R G B) facing up under
LIGHTS and the ambient light, lit as the mesh shader lights a matte surface."
  (flet ((channel (c i) (if (vec3-p c) (ecase i (0 (vec3-x c)) (1 (vec3-y c)) (2 (vec3-z c))) (nth i c))))
    (loop for i below 3
          for albedo = (channel colour i)
          collect (sqrt (min 1d0 (* albedo albedo
                                    (+ (channel *ambient-colour* i)
                                       (loop for (direction light) in lights
                                             sum (* (max 0d0 (vec3-y direction)) (channel light i))))))))))

(defun contact-shadow (bounds surface)
  "The blob shadow (X Z RADIUS HEIGHT STRENGTH) of a body whose box is BOUNDS,
a list (X0 Y0 Z0 X1 Y1 Z1), on a surface at height SURFACE: as wide as the
body, lying 2 mm above the surface, fading as the body rises (gone 0.5 m up)."
  (destructuring-bind (x0 y0 z0 x1 y1 z1) bounds
    (declare (ignore y1))
    (let ((rise (max 0d0 (- y0 surface))))
      (list (* 0.5d0 (+ x0 x1)) (* 0.5d0 (+ z0 z1))
            (* (max 0.04d0 (* 0.62d0 (max (- x1 x0) (- z1 z0)))) (+ 1 rise))
            (+ surface 0.002d0)
            (* 0.55d0 (max 0d0 (- 1 (* 2 rise))))))))

(defun vertex-bounds (vertices)
  "The corners of the box around the interleaved VERTICES (+VERTEX-FLOATS+ per
vertex, at least one), as a list (X0 Y0 Z0 X1 Y1 Z1) of single-floats."
  (declare (type float-vector vertices) (optimize (speed 3) (safety 1)))
  (let ((x0 (aref vertices 0)) (y0 (aref vertices 1)) (z0 (aref vertices 2)))
    (declare (type single-float x0 y0 z0))
    (let ((x1 x0) (y1 y0) (z1 z0))
      (declare (type single-float x1 y1 z1))
      (loop for i of-type fixnum from 0 below (length vertices) by +vertex-floats+
            do (let ((x (aref vertices i)) (y (aref vertices (+ i 1))) (z (aref vertices (+ i 2))))
                 (setf x0 (min x0 x) y0 (min y0 y) z0 (min z0 z) x1 (max x1 x) y1 (max y1 y) z1 (max z1 z))))
      (list x0 y0 z0 x1 y1 z1))))

(defun floor-height (scene-meshes)
  "Where the floor goes: at y = 0, or under the lowest prop (a table stands on it)."
  (reduce #'min (remove-if (lambda (m) (typep (scene-mesh-object m) 'body)) scene-meshes)
          :key (lambda (m) (float (second (vertex-bounds (scene-mesh-vertices m))) 1d0))
          :initial-value 0d0))

(defun shadow-surface (bounds props ground)
  "The height of what a body with box BOUNDS stands on: the highest top of the
PROPS (scene meshes) under its centre and below its middle (its toes and tail
may dip into a table), else GROUND."
  (destructuring-bind (x0 y0 z0 x1 y1 z1) bounds
    (let ((x (* 0.5 (+ x0 x1))) (z (* 0.5 (+ z0 z1))) (middle (* 0.5 (+ y0 y1))))
      (reduce #'max props
              :initial-value ground
              :key (lambda (prop)
                     (destructuring-bind (px0 py0 pz0 px1 py1 pz1) (vertex-bounds (scene-mesh-vertices prop))
                       (declare (ignore py0))
                       (if (and (<= px0 x px1) (<= pz0 z pz1) (<= py1 middle))
                           (float py1 1d0)
                           ground)))))))


;;;# The floor

(defparameter *floor-rings* '(0 1 2 3 4 5.5 7 9 11 13.5 16 19 22 25 40 70)
  "Radii (metres) of the floor grid's rings: its fade is computed at each, so
they are close together where it fades (see DRAW-FLOOR).")

(defun floor-grid (&optional (sectors 48))
  "The vertices and indices (two values) of a disc in the plane y = 0 made of
*FLOOR-RINGS* and SECTORS spokes, facing up."
  (let* ((rings (length *floor-rings*))
         (vertices (make-array (* +vertex-floats+ rings sectors) :element-type 'single-float
                                                                  :initial-element 0f0))
         (indices (make-array (* 6 (1- rings) sectors) :element-type '(unsigned-byte 32))))
    (loop for radius in *floor-rings*
          for ring from 0
          do (dotimes (k sectors)
               (let ((angle (/ (* 2 pi k) sectors))
                     (at (* +vertex-floats+ (+ k (* ring sectors)))))
                 (setf (aref vertices at) (float (* radius (cos angle)) 1f0)
                       (aref vertices (+ at 2)) (float (* radius (sin angle)) 1f0)
                       (aref vertices (+ at 4)) 1f0))))
    (dotimes (ring (1- rings) (values vertices indices))
      (dotimes (k sectors)
        (flet ((vertex (r j) (+ (mod j sectors) (* r sectors))))
          (replace indices (list (vertex ring k) (vertex (1+ ring) (1+ k)) (vertex (1+ ring) k)
                                 (vertex ring k) (vertex ring (1+ k)) (vertex (1+ ring) (1+ k)))
                   :start1 (* 6 (+ k (* ring sectors)))))))))
