// Zones: regions of space that decide which ballast particles become clumps (the rest stay balls),
// in the multi-layer shape model. A zone is given as one line of text, e.g.
//   box(-1.6, -0.3, 0.2, 1.6, 0.3, 0.6) | halfspace(0, 0, 0.265, 0, 0, -1) - sphere(0, 0, 0, 0.1)
// The language, every shape and the pilot zone: docs/zones.md.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dem/engine/types.h"

namespace trackbed::dem {

// An axis-aligned box (Eigen's: an empty box has isEmpty() true).
using Bounds = Eigen::AlignedBox3d;

// What a pilot() term found in its run, for the run that uses the zone to report.
struct PilotSummary {
  std::string snapshot;             // the chosen snapshot file
  long step = 0;                    // its step
  double time = 0;                  // its time, s
  double sleeper_displacement = 0;  // the sleeper's displacement there, m (>= the one asked for)
  int selected_bodies = 0;          // bodies that moved more than the threshold
  int total_bodies = 0;             // bodies in the pilot run
};

class Zone {
 public:
  virtual ~Zone() = default;

  // Every shape is a closed set: a point on its boundary is inside (docs/zones.md#shapes).
  virtual bool contains(const Vec3& x) const = 0;
  // A box holding the zone; std::nullopt when the zone is unbounded (a half-space, all); an empty
  // box for an empty zone. Not always the tightest box (a difference keeps its left side's).
  virtual std::optional<Bounds> bounds() const = 0;

  // The canonical text: numbers in their shortest exact form, '+' written '|', only the
  // parentheses precedence needs, pilot paths resolved. parse_zone(to_string()) gives a zone
  // that classifies every point the same way.
  std::string to_string() const;
  // What every pilot() term of the zone found, in the order of the text.
  std::vector<PilotSummary> pilot_summaries() const;

  // For the set operations, which print and search their operands. Precedence: 1 for '|' and
  // '-', 2 for '&', 3 for a shape.
  virtual int precedence() const { return 3; }
  virtual void print(std::string& out) const = 0;
  virtual void collect_pilot_summaries(std::vector<PilotSummary>&) const {}
};

using ZonePtr = std::shared_ptr<const Zone>;

// Parses a zone expression (docs/zones.md#grammar). `where` names it in messages
// ("case.prm: sample/clump zone"); relative pilot folders resolve against base_folder (the case
// file's folder; empty: the working directory). Throws InputError with one line naming `where`,
// the character position (1-based) and what was expected there.
ZonePtr parse_zone(const std::string& text, const std::string& where,
                   const std::string& base_folder);

// The shapes and set operations, for code that builds zones without text. The shapes throw
// InputError (without a position: the parser adds it) for arguments docs/zones.md refuses.
ZonePtr all_zone();
ZonePtr no_zone();
ZonePtr box_zone(const Vec3& lower, const Vec3& upper);  // upper > lower on every axis
ZonePtr halfspace_zone(const Vec3& point, const Vec3& outward_normal);  // (x - p) . n <= 0
ZonePtr sphere_zone(const Vec3& centre, double radius);                 // radius > 0
// A simple polygon in the plane normal to `axis` (0, 1, 2 for x, y, z), in the coordinates
// (y, z), (x, z) or (x, y), extruded over lo <= x[axis] <= hi.
ZonePtr prism_zone(int axis, double lo, double hi, const std::vector<Eigen::Vector2d>& polygon);
ZonePtr union_zone(ZonePtr a, ZonePtr b);
ZonePtr intersection_zone(ZonePtr a, ZonePtr b);
ZonePtr difference_zone(ZonePtr a, ZonePtr b);  // in a and not in b

}  // namespace trackbed::dem
