// The particle file: one body per row of a CSV table (format in docs/formats.md).
#pragma once

#include <map>
#include <string>

#include "dem/engine/clump_template.h"
#include "dem/engine/material.h"
#include "dem/engine/particles.h"

namespace trackbed::dem {

// Appends the bodies of the particle CSV `path` to `particles`. Ball rows need a radius; clump
// rows name a template: (x, y, z) is where the origin of the template's own frame goes, (qw, qx,
// qy, qz) rotates that frame into the world, and `scale` scales the template about its origin.
void read_particle_file(const std::string& path, const MaterialTable& materials,
                        const std::map<std::string, ClumpTemplate>& templates,
                        Particles& particles);

}  // namespace trackbed::dem
