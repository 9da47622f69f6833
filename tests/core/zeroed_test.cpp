// Zeroed<T> off the images (FW_ZEROED_STORAGE 0: host tests, tools): the block is cleared at construction
// wherever its owner lives, here over storage that held other bytes. On the images the block is not cleared
// and relies on .bss; the twin tests run those images on SRAM filled with a pseudo-random pattern.
#include "core/zeroed.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <new>

#include "core/time.hpp"

namespace {

struct Block {
  uint8_t flags;
  uint16_t count;
  fw::Instant at;
  uint8_t buffer[13];
};

struct Owner {
  uint8_t small = 7;
  fw::Zeroed<Block> state;
};

static_assert(!FW_ZEROED_STORAGE, "host builds clear Zeroed blocks");

TEST(Zeroed, IsClearedAtConstructionOverDirtyStorage) {
  alignas(Owner) unsigned char storage[sizeof(Owner)];
  for (unsigned char& b : storage)
    b = 0xA5;
  Owner* o = new (storage) Owner;
  EXPECT_EQ(o->small, 7);
  EXPECT_EQ(o->state->flags, 0);
  EXPECT_EQ(o->state->count, 0);
  EXPECT_EQ(o->state->at.us, 0U);
  for (uint8_t b : o->state->buffer)
    EXPECT_EQ(b, 0);
  o->state->count = 513;
  (*o->state).flags = 2;
  const Owner& c = *o;
  EXPECT_EQ(c.state->count, 513);
  EXPECT_EQ((*c.state).flags, 2);
  EXPECT_EQ(fw::addressOf(o->state), &*o->state);
  o->~Owner();
}

}  // namespace
