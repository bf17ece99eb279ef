/* Private helpers shared by the scene module's sources. */
#ifndef GEOM_SRC_SCENE_INTERNAL_H
#define GEOM_SRC_SCENE_INTERNAL_H

#include "geom/scene.h"

/* World-space bounding box of a draw (its mesh's box, transformed). */
geom_aabb geom__scene_draw_bbox(const geom_scene_draw *d);

#endif
