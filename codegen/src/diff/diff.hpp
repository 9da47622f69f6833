// `regmapgen diff`: what changed between two versions of a register map, one line per entry, so a map
// regenerated from a new TRM revision is a reviewable change.
//
// Entries are matched by family, kind, class/subclass and name (ignoring case, spaces, '_' and '-'); an
// entry left unmatched on both sides at the same family, kind and address is a rename. Compared: address,
// span, type, min, max, default (as numbers: 0x0A equals 10), unit with scale, and the fields of the
// entry's fieldset when both versions have one (by name without its "[1:0]"; a field at the same bits under
// another name is a rename). Descriptions, notes,
// sources, access and identifiers are not compared: imports cannot know them. Lines, in kind and address
// order:
//   + datamem 'Foo' (Settings:Protection) 0x9400 U1
//   - command 'TS1 Temperature' 0x70 I2
//   ~ datamem 'CUV Threshold' (Settings:Protection) 0x9275: default 50 -> 52; unit 50.6 mV -> mV
#pragma once

#include <string>
#include <vector>

#include "model/model.hpp"

namespace regmapgen {

struct MapDiff {
  std::vector<std::string> lines;  // "+ ...", "- ...", "~ ..."
  int added = 0, removed = 0, changed = 0, unchanged = 0;
  bool differs() const { return added + removed + changed > 0; }
};

// Compares `before` with `after`. With `onlyKindsOfAfter`, kinds `after` has no entry of are left out
// (an imported table holds one kind; the map it is compared with holds all of them).
MapDiff diffModels(const Model& before, const Model& after, bool onlyKindsOfAfter = false);

}  // namespace regmapgen
