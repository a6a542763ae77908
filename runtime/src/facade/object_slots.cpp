#include "object_slots.h"

#include <algorithm>

namespace svit::gl {
namespace {

// live_ is sorted by id: ids are handed out ascending, so add() appends.
auto findLive(const std::vector<std::pair<ObjectId, uint32_t>>& live, ObjectId id) {
  return std::lower_bound(
      live.begin(), live.end(), id,
      [](const std::pair<ObjectId, uint32_t>& e, ObjectId v) { return e.first < v; });
}

}  // namespace

ObjectSlots::Added ObjectSlots::add() {
  if (next_id_ == kInvalidId) return {};  // every id given: none is ever reused
  Added added;
  added.id = next_id_++;
  if (free_slots_.empty()) {
    added.slot = uint32_t(slot_id_.size());
    added.new_slot = true;
    slot_id_.push_back(added.id);
  } else {
    added.slot = free_slots_.back();
    free_slots_.pop_back();
    slot_id_[added.slot] = added.id;
  }
  live_.push_back({added.id, added.slot});
  return added;
}

void ObjectSlots::remove(ObjectId id) {
  const auto it = findLive(live_, id);
  if (it == live_.end() || it->first != id) return;
  slot_id_[it->second] = kInvalidId;
  free_slots_.push_back(it->second);
  live_.erase(it);
}

uint32_t ObjectSlots::slotOf(ObjectId id) const {
  const auto it = findLive(live_, id);
  return it == live_.end() || it->first != id ? kNoSlot : it->second;
}

ObjectId ObjectSlots::idOf(uint32_t slot) const {
  return slot < slot_id_.size() ? slot_id_[slot] : kInvalidId;
}

std::vector<ObjectId> ObjectSlots::liveIds() const {
  std::vector<ObjectId> ids;
  ids.reserve(live_.size());
  for (const auto& [id, slot] : live_) ids.push_back(id);
  return ids;
}

size_t ObjectSlots::bytes() const {
  return live_.capacity() * sizeof(live_[0]) + slot_id_.capacity() * sizeof(ObjectId) +
         free_slots_.capacity() * sizeof(uint32_t);
}

}  // namespace svit::gl
