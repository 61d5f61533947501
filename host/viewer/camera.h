/*
 * host/viewer/camera.h: the camera the viewer (`lightgraph view`) drives with the mouse and
 * keyboard, overriding the scene's active camera (lightgraph/scene.h lg_camera).
 *
 * An lg_vcam is a look-at camera: position, target and up in world space, with the
 * lg_camera fields that go with them. It is made from the graph's camera and the scene's
 * bounds (lg_vcam_init), changed by the input functions below and turned back into an
 * lg_camera (lg_vcam_to_camera) that the viewer hands to every node that renders the scene.
 *
 * Conventions:
 *   - Pixels as the window reports them: x to the right, y down; `h` is the view's height.
 *     A drag across the full height turns by 180 degrees (orbit and look alike).
 *   - Orbit and look turn about the world up, +Y (yaw), and about the camera's right axis
 *     (pitch). Pitch stops 0.5 degrees short of the poles, so the view never flips; the
 *     stored up is the world up made perpendicular to the view direction (a roll the graph's
 *     camera had is dropped on the first turn).
 *   - Orbit: dragging right moves the eye to the left round the target (the scene turns with
 *     the pointer, as if grabbed); dragging down raises the eye (the top of the scene comes
 *     towards the user).
 *   - Look (fly): moving right turns the view right; moving down looks down.
 *   - `scale` is the scene's size (half the bounds' diagonal): move speeds are in scales per
 *     second and the zoom floor is 1e-4 scale.
 *
 * Every function leaves the camera finite and valid (target != position, up a unit vector
 * perpendicular to the view direction), whatever its input: a non-finite or absurd argument
 * (NaN, h <= 0, negative dt) changes nothing. None of them calls GL or GLFW.
 */
#ifndef LG_HOST_VIEWER_CAMERA_H
#define LG_HOST_VIEWER_CAMERA_H

#include "lightgraph/scene.h"

typedef enum lg_vcam_mode { LG_VCAM_ORBIT = 0, LG_VCAM_FLY } lg_vcam_mode;

typedef struct lg_vcam {
    lg_vcam_mode mode;                   /* which input the viewer routes where; the
                                              functions below work in either mode */
    float position[3], target[3], up[3]; /* world; target - position never zero */
    float yfov, znear, zfar, aspect;     /* as lg_camera */
    float scale;                         /* the scene's size (bounding radius), for speeds */
} lg_vcam;

/* From the graph's camera c and the scene bounds: scale = half the bounds' diagonal (1 when
 * the bounds are empty, not finite or a single point). c may be NULL, or hold values a camera
 * cannot have (not finite, position = target, yfov outside (0, 3.1)): what is missing is made
 * up as scene_tools' `camera` node does in orbit mode (looking at the bounds' centre from
 * azimuth 0, elevation 20 degrees, far enough for the bounding sphere to fit; yfov 45
 * degrees). The mode is LG_VCAM_ORBIT. bmin and bmax may be NULL (empty bounds). */
void lg_vcam_init(lg_vcam *v, const lg_camera *c, const float bmin[3], const float bmax[3]);

/* The camera as an lg_camera: name NULL, reserved fields zero. */
void lg_vcam_to_camera(const lg_vcam *v, lg_camera *out);

/* Orbit: dragging by (dx, dy) pixels in a view h pixels tall turns the eye about the target
 * (distance kept): yaw -pi dx / h about +Y, pitch pi dy / h about the camera's right axis. */
void lg_vcam_orbit(lg_vcam *v, double dx, double dy, int h);

/* Pan: moves eye and target together so that the point under the pointer at the target's
 * depth follows the pointer (dx, dy pixels, view h pixels tall, vertical fov yfov). */
void lg_vcam_pan(lg_vcam *v, double dx, double dy, int h);

/* Zoom: d wheel clicks (> 0 towards the target): distance *= 0.85^d, kept within
 * [1e-4 scale, 1e9 scale] (a camera already farther than the ceiling may still zoom in). */
void lg_vcam_zoom(lg_vcam *v, double d);

/* Fly, mouse look: (dx, dy) pixels in a view h pixels tall turn the view direction (yaw
 * about +Y, pitch about the right axis, as orbit's angles); the eye stays, the target is
 * kept in front at the same distance. */
void lg_vcam_look(lg_vcam *v, double dx, double dy, int h);

/* Fly, move: rul = (right, up, forward), each clamped to [-1, 1] and the vector to length 1
 * at most (a diagonal is no faster), along the camera's own axes (right, up, view
 * direction), for dt seconds at `speed` scene scales per second. The target moves with the
 * eye. */
void lg_vcam_move(lg_vcam *v, const float rul[3], double dt, double speed);

/* The camera as a graph node to paste into a graph file, malloc'd (the caller frees), or
 * NULL when name or scene_ref is not a graph NAME ([A-Za-z_][A-Za-z0-9_]*) or memory runs
 * out:
 *
 *   NAME = camera {
 *       scene = SCENE
 *       mode = look_at
 *       position = [x, y, z]
 *       target = [x, y, z]
 *       up = [x, y, z]
 *       fov_deg = f
 *       znear = n               (only when non-zero; the same for zfar and aspect)
 *   }
 *
 * Numbers are printed with %.6g; when six digits would change the eye-to-target vector by
 * more than 1e-5 (relative length, or radians: an eye very close to a target that is far
 * from the origin, as at the zoom floor), position and target use %.9g, which gives the
 * floats back exactly. The text parses, checks and renders as a scene_tools `camera` node. */
char *lg_vcam_node_text(const lg_vcam *v, const char *name, const char *scene_ref);

/* Near and far planes that hold the box [bmin, bmax] as seen from the camera, by the rule of
 * scene_tools' `camera` node (far: the farthest corner along the view x 1.01; near: the
 * nearest x 0.99, at least far / 1000): the graph camera's planes were fitted to where it
 * stood, and a camera moved outside them would clip the scene. Without usable bounds the
 * planes are the target's distance / 100 and x 100. */
void lg_vcam_fit_clip(lg_vcam *v, const float bmin[3], const float bmax[3]);

#endif
