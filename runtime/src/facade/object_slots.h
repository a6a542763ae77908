#pragma once
// Public object ids and the internal slots behind them. Ids only grow (a
// removed id stays stale and is refused forever: the API's contract);
// slots are reused after a removal, so everything the runtime keeps per
// object (its record, its kObjectShooters shooter groups, their emitters)
// is as long as the most objects alive at once, not every object ever
// added: a game that adds and removes props for hours keeps it flat.

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "svit/runtime.h"

namespace svit::gl {

/// No slot: the id was never given, or its object was removed.
inline constexpr uint32_t kNoSlot = 0xffffffffu;

class ObjectSlots {
 public:
  struct Added {
    ObjectId id = kInvalidId;
    uint32_t slot = kNoSlot;
    bool new_slot = false;  ///< slot == slotCount() - 1 and never used before
  };
  /// A new id (one above the last given) and its slot: the one freed most
  /// recently, else a new one at the end. kInvalidId with kNoSlot once
  /// 2^32 - 1 ids have been given (the caller refuses the object).
  Added add();
  /// Frees the slot of a live `id` for the next add(); a stale or unknown
  /// id changes nothing (the runtime refuses those before it gets here).
  void remove(ObjectId id);
  /// The slot of a live id, or kNoSlot (never given, or removed).
  uint32_t slotOf(ObjectId id) const;
  /// The live id in `slot`, or kInvalidId (free, or out of range).
  ObjectId idOf(uint32_t slot) const;
  /// The live ids, ascending.
  std::vector<ObjectId> liveIds() const;
  uint32_t liveCount() const { return uint32_t(live_.size()); }
  /// Slots ever made: live plus free.
  uint32_t slotCount() const { return uint32_t(slot_id_.size()); }
  /// Bytes its tables hold (capacity).
  size_t bytes() const;

 private:
  std::vector<std::pair<ObjectId, uint32_t>> live_;  ///< (id, slot), ascending by id
  std::vector<ObjectId> slot_id_;                    ///< per slot: its live id or kInvalidId
  std::vector<uint32_t> free_slots_;                 ///< a stack: the last freed is reused first
  ObjectId next_id_ = 0;
};

}  // namespace svit::gl
