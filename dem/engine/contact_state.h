// The springs of a model's live contacts, saved with a sample or a checkpoint so that a reloaded
// model starts with the contact forces it had (a bed restarted without them first loses its
// frictional support and re-settles). Elements are named by the id of their body and their rank
// within it, which survive the reordering of bodies at setup and a reload.
#pragma once

#include <cstdint>
#include <vector>

#include "dem/engine/types.h"

namespace trackbed::dem {

struct ElementKey {
  std::int64_t body_id;
  int rank;  // element index within the body
};

struct SavedPairContact {
  ElementKey i, j;
  Vec3 shear, roll;
};

// A contact with a plane wall (wall < number of planes, slot 0) or a mesh (wall = number of planes
// + mesh index; slot = the contact's index among the element's contacts with that mesh).
struct SavedWallContact {
  int wall, slot;
  ElementKey element;
  Vec3 shear, roll, normal;
};

struct ContactState {
  std::vector<SavedPairContact> pairs;
  std::vector<SavedWallContact> walls;
};

}  // namespace trackbed::dem
