// Register-map descriptors: the compile-time contract between the headers regmapgen generates from
// regmaps/<family>/*.yaml and the drivers that use them.
//
// What a descriptor is
// - Every table entry (a direct command, subcommand, data-memory parameter, BQ79616 register, SBS command,
// MAC
//   subcommand...) becomes one `inline constexpr` object in a generated header, e.g.
//     fw::regmap::bq769x2::cmd::Cell1Voltage   // Descriptor<bq769x2::Family, Spec{...}, std::int16_t>
//   Everything it knows lives in its *type*: the object is empty, passing it by value costs nothing, and
//   `D::address`, `D::size`, `D::access`... are constant expressions inside any template that receives it.
//   Nothing here allocates, uses floating point or carries a string: the target image only gets the bytes the
//   driver itself builds. Names and other text live in the separate runtime table (regmap/table.hpp).
// - `D::value_type` is the C++ type of the decoded value:
//     std::uint8_t ... std::int32_t   U1/U2/U4, I1/I2/I4 and H1/H2/H4 without a field layout
//     bits::X                         a generated bit-field value type (H1/H2/H4 or U1... with a fieldset)
//     enums::X                        a generated enum (an entry whose whole value is a coded setting)
//     F4                              a 32-bit IEEE-754 float kept as its bit pattern (no float maths here)
//     std::array<E, N>                fixed arrays of integers ("16xI2") and fixed byte blocks ("B6" ->
//     E=uint8) Block<N>                        variable-length SMBus / subcommand blocks of at most N bytes
//     ("B", "S") NoData                          command-only subcommands ("type: none"); there is nothing to
//     read
// - `D::order` is the byte order on the wire: little-endian for BQ769x2/BQ7690x/BQ4050, big-endian for the
//   BQ79616 (regmapgen sets it per kind).
// - `D::unit` and `D::scale` give the physical meaning of one LSB as an exact ratio: Cell 1 Voltage is
//   {MilliVolt, 1/1}, Int Temperature {Kelvin, 1/10}, a BQ79616 cell reading {MicroVolt, 19073/100}.
// - min/max/default are known only where the TRM gives them; `D::hasDefault` says so, and `defaultValue()`
//   only compiles when it is true. F4 limits are stored as IEEE-754 bit patterns computed by regmapgen.
//
// Access is a compile-time property
// - decode() exists only for Readable descriptors and encode() only for Writable ones, so writing a read-only
//   command or reading a command-only subcommand is a compile error (tests/codegen has the compile-fail
//   test).
// - Drivers constrain their own templates with the same concepts:
//     template <regmap::Readable D> Status readDirect(D d, ...);
//     template <regmap::CommandOnly D> Status sendSubcommand(D d);
//   `ConfigUpdateOnly` marks data memory that may only be written in CONFIG_UPDATE mode (BQ769x2/BQ7690x);
//   `WriteOneToClear` marks latched status registers cleared by writing 1s (BQ769x2/BQ7690x Alarm Status).
//
// Header-only, freestanding-friendly (no <string>, no heap, no exceptions); every function is constexpr and
// usable from ISRs.
#pragma once

#include <array>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>

namespace fw::regmap {

// What kind of table entry a descriptor describes; decides how a driver reaches it on the bus.
enum class Kind : std::uint8_t {
  Command,     // BQ769x2/BQ7690x direct command: a byte address in the 0x00..0x7F command space
  Subcommand,  // BQ769x2/BQ7690x subcommand: a 16-bit code written to 0x3E/0x3F, data in 0x40..0x5F
  DataMemory,  // BQ769x2/BQ7690x data memory: a 16-bit address reached through the subcommand window
  Register,    // BQ79616 8-bit register at a 16-bit address
  Value,       // BQ79616 multi-byte reading spanning consecutive registers (e.g. VCELL16_HI/LO as one I2)
  Sbs,         // BQ4050 SBS command (SMBus word or block)
  Mac,         // BQ4050 ManufacturerAccess subcommand (via 0x00/0x23 or ManufacturerBlockAccess 0x44)
  DataFlash,   // BQ4050 data flash (MAC addresses 0x4000..0x5FFF)
};

enum class ByteOrder : std::uint8_t { Little, Big };

// Who may do what with an entry. The YAML spells these r, w, rw, rw1c, cmd and config_update.
enum class Access : std::uint8_t {
  ReadOnly,         // r
  WriteOnly,        // w: a payload is written, nothing can be read back (e.g. FET_CONTROL)
  ReadWrite,        // rw
  ReadWrite1Clear,  // rw1c: readable; writing a 1 to a bit clears that bit (latched status)
  CommandOnly,      // cmd: sending the code is the whole operation, there is no data either way
  ConfigUpdate,     // config_update: readable any time, writable only in CONFIG_UPDATE mode
};

constexpr bool isReadable(Access a) {
  return a == Access::ReadOnly || a == Access::ReadWrite || a == Access::ReadWrite1Clear ||
         a == Access::ConfigUpdate;
}
constexpr bool isWritable(Access a) {
  return a == Access::WriteOnly || a == Access::ReadWrite || a == Access::ReadWrite1Clear ||
         a == Access::ConfigUpdate;
}

// Physical unit of one LSB (before `scale`). The YAML spells each with the symbol unitSymbol() returns;
// regmapgen's self-test translation unit checks that both lists agree.
enum class Unit : std::uint8_t {
  None,           // ""        a code, a flag word or a plain number
  MilliVolt,      // "mV"
  MicroVolt,      // "uV"
  NanoVolt,       // "nV"
  UserVolt,       // "userV"   BQ769x2: mV or 10 mV per DA Configuration[USER_VOLTS_CV]
  MilliAmp,       // "mA"
  UserAmp,        // "userA"   BQ769x2/BQ7690x: 0.1/1/10/100 mA per DA Configuration[USER_AMPS]
  UserAmpHour,    // "userAh"
  MilliAmpHour,   // "mAh"
  CentiWattHour,  // "cWh"
  Capacity,       // "mAh|10mWh" SBS: mAh, or 10 mWh when BatteryMode[CAPM] = 1
  Rate,           // "mA|10mW"   SBS: mA, or 10 mW when BatteryMode[CAPM] = 1
  Kelvin,         // "K"
  DegreeCelsius,  // "degC"
  Second,         // "s"
  Millisecond,    // "ms"
  Microsecond,    // "us"
  Minute,         // "min"
  Hour,           // "h"
  MilliOhm,       // "mOhm"
  Percent,        // "percent"
  Count,          // "counts"  raw ADC or counter counts
  Byte,           // "bytes"
  Cycle,          // "cycles"
};

constexpr const char* unitSymbol(Unit u) {
  switch (u) {
    case Unit::None:
      return "";
    case Unit::MilliVolt:
      return "mV";
    case Unit::MicroVolt:
      return "uV";
    case Unit::NanoVolt:
      return "nV";
    case Unit::UserVolt:
      return "userV";
    case Unit::MilliAmp:
      return "mA";
    case Unit::UserAmp:
      return "userA";
    case Unit::UserAmpHour:
      return "userAh";
    case Unit::MilliAmpHour:
      return "mAh";
    case Unit::CentiWattHour:
      return "cWh";
    case Unit::Capacity:
      return "mAh|10mWh";
    case Unit::Rate:
      return "mA|10mW";
    case Unit::Kelvin:
      return "K";
    case Unit::DegreeCelsius:
      return "degC";
    case Unit::Second:
      return "s";
    case Unit::Millisecond:
      return "ms";
    case Unit::Microsecond:
      return "us";
    case Unit::Minute:
      return "min";
    case Unit::Hour:
      return "h";
    case Unit::MilliOhm:
      return "mOhm";
    case Unit::Percent:
      return "percent";
    case Unit::Count:
      return "counts";
    case Unit::Byte:
      return "bytes";
    case Unit::Cycle:
      return "cycles";
  }
  return "?";
}

// One LSB = num/den units (exact; 190.73 uV is {19073, 100}). Always den > 0.
struct Ratio {
  std::int32_t num = 1;
  std::int32_t den = 1;
  friend constexpr bool operator==(const Ratio&, const Ratio&) = default;
};

// Everything regmapgen knows about an entry, as a structural literal so it can be a template argument.
// Limits are raw register values (before scale), sign-extended; F4 limits are IEEE-754 bit patterns.
struct Spec {
  Kind kind = Kind::Command;
  std::uint32_t address = 0;
  std::uint16_t size = 0;  // bytes of the value on the wire; for variable-length blocks the maximum
  bool variable = false;   // a block whose length is reported by the device (SMBus count, 0x61 length)
  ByteOrder order = ByteOrder::Little;
  Access access = Access::ReadOnly;
  Unit unit = Unit::None;
  Ratio scale{};
  bool hasMin = false;
  bool hasMax = false;
  bool hasDefault = false;
  std::int64_t min = 0;
  std::int64_t max = 0;
  std::int64_t dflt = 0;
};

// `bits` with the field at `mask` (its lowest bit at `lsb`) set to `value`; bits outside the field are kept
// and value bits beyond the field dropped. The generated bit-field types' with_<field>() use it.
template <std::unsigned_integral R>
constexpr R withField(R bits, R mask, unsigned lsb, R value) {
  return static_cast<R>((bits & ~mask) | ((value << lsb) & mask));
}

// --- value types that are not plain integers -------------------------------------------------------------

// Command-only subcommands carry no data.
struct NoData {
  friend constexpr bool operator==(NoData, NoData) = default;
};

// A TI "F4" value (IEEE-754 binary32, little-endian on the wire) kept as its bit pattern: the firmware never
// does float arithmetic on it; host tools can std::bit_cast<float>(value.raw()).
struct F4 {
  using raw_type = std::uint32_t;
  raw_type bits = 0;
  constexpr raw_type raw() const { return bits; }
  static constexpr F4 fromRaw(raw_type r) { return F4{r}; }
  friend constexpr bool operator==(const F4&, const F4&) = default;
};

// A variable-length block of at most N bytes; `length` bytes of `data` are valid.
template <std::size_t N>
struct Block {
  std::uint8_t length = 0;
  std::array<std::uint8_t, N> data{};
  constexpr std::span<const std::uint8_t> bytes() const { return {data.data(), length}; }
  friend constexpr bool operator==(const Block&, const Block&) = default;
};

// Generated bit-field value types (bits::X) and F4 model this: a raw integer with named views.
template <class T>
concept BitsValue = requires(const T t, typename T::raw_type r) {
  requires std::unsigned_integral<typename T::raw_type>;
  { t.raw() } -> std::same_as<typename T::raw_type>;
  { T::fromRaw(r) } -> std::same_as<T>;
};

namespace detail {

template <class T>
struct Codec;  // size in bytes, load from / store to the wire in a given byte order

template <std::unsigned_integral U>
constexpr U loadUnsigned(const std::uint8_t* p, ByteOrder order) {
  U v = 0;
  for (std::size_t i = 0; i < sizeof(U); ++i) {
    const std::size_t shift = (order == ByteOrder::Little ? i : sizeof(U) - 1 - i) * 8;
    v = static_cast<U>(v | (static_cast<U>(p[i]) << shift));
  }
  return v;
}

template <std::unsigned_integral U>
constexpr void storeUnsigned(std::uint8_t* p, U v, ByteOrder order) {
  for (std::size_t i = 0; i < sizeof(U); ++i) {
    const std::size_t shift = (order == ByteOrder::Little ? i : sizeof(U) - 1 - i) * 8;
    p[i] = static_cast<std::uint8_t>(v >> shift);
  }
}

template <std::integral T>
struct Codec<T> {
  using U = std::make_unsigned_t<T>;
  static constexpr std::size_t size = sizeof(T);
  // Signed values convert through the unsigned one: 0xFFFF loads as -1 without undefined behaviour.
  static constexpr T load(const std::uint8_t* p, ByteOrder o) {
    return static_cast<T>(loadUnsigned<U>(p, o));
  }
  static constexpr void store(std::uint8_t* p, T v, ByteOrder o) {
    storeUnsigned<U>(p, static_cast<U>(v), o);
  }
};

template <class T>
requires std::is_enum_v<T>
struct Codec<T> {
  using Under = std::underlying_type_t<T>;
  static constexpr std::size_t size = sizeof(Under);
  static constexpr T load(const std::uint8_t* p, ByteOrder o) {
    return static_cast<T>(Codec<Under>::load(p, o));
  }
  static constexpr void store(std::uint8_t* p, T v, ByteOrder o) {
    Codec<Under>::store(p, static_cast<Under>(v), o);
  }
};

template <BitsValue T>
struct Codec<T> {
  using R = typename T::raw_type;
  static constexpr std::size_t size = sizeof(R);
  static constexpr T load(const std::uint8_t* p, ByteOrder o) { return T::fromRaw(Codec<R>::load(p, o)); }
  static constexpr void store(std::uint8_t* p, const T& v, ByteOrder o) { Codec<R>::store(p, v.raw(), o); }
};

template <class E, std::size_t N>
struct Codec<std::array<E, N>> {
  static constexpr std::size_t size = N * Codec<E>::size;
  static constexpr std::array<E, N> load(const std::uint8_t* p, ByteOrder o) {
    std::array<E, N> v{};
    for (std::size_t i = 0; i < N; ++i)
      v[i] = Codec<E>::load(p + i * Codec<E>::size, o);
    return v;
  }
  static constexpr void store(std::uint8_t* p, const std::array<E, N>& v, ByteOrder o) {
    for (std::size_t i = 0; i < N; ++i)
      Codec<E>::store(p + i * Codec<E>::size, v[i], o);
  }
};

template <>
struct Codec<NoData> {
  static constexpr std::size_t size = 0;
};

template <class T>
struct IsBlock : std::false_type {};
template <std::size_t N>
struct IsBlock<Block<N>> : std::true_type {};

// A variable-length entry decodes to a Block; any other to a type whose wire size is exactly Spec::size.
template <class T>
constexpr bool sizeMatches(const Spec& s) {
  if constexpr (IsBlock<T>::value) {
    return s.variable;
  } else {
    return !s.variable && Codec<T>::size == s.size;
  }
}

// Builds a value from a raw limit stored in Spec (only for scalar value types).
template <class T>
constexpr T fromRawLimit(std::int64_t raw) {
  if constexpr (BitsValue<T>) {
    return T::fromRaw(static_cast<typename T::raw_type>(raw));
  } else {
    return static_cast<T>(raw);
  }
}

}  // namespace detail

// Bytes on the wire for a fixed-size value type (what regmapgen's static_asserts compare with Spec::size).
template <class T>
inline constexpr std::size_t wireSize = detail::Codec<T>::size;

// The descriptor template. Family is a per-family tag type, so identical specs of two families stay
// distinct types; S holds the facts; T is the value type (see the header comment).
template <class Family, Spec S, class T>
struct Descriptor {
  using family_type = Family;
  using value_type = T;

  static constexpr Spec spec = S;
  static constexpr Kind kind = S.kind;
  static constexpr std::uint32_t address = S.address;
  static constexpr std::size_t size = S.size;
  static constexpr ByteOrder order = S.order;
  static constexpr Access access = S.access;
  static constexpr Unit unit = S.unit;
  static constexpr Ratio scale = S.scale;
  static constexpr bool hasMin = S.hasMin;
  static constexpr bool hasMax = S.hasMax;
  static constexpr bool hasDefault = S.hasDefault;

  static_assert(S.scale.den > 0, "regmapgen emits scales with a positive denominator");
  static_assert(detail::sizeMatches<T>(S), "value type and wire size disagree");

  // The TRM default / limits as values of the entry's type; each compiles only where the TRM gives one.
  static constexpr T defaultValue() requires(S.hasDefault) { return detail::fromRawLimit<T>(S.dflt); }
  static constexpr T minValue() requires(S.hasMin) { return detail::fromRawLimit<T>(S.min); }
  static constexpr T maxValue() requires(S.hasMax) { return detail::fromRawLimit<T>(S.max); }
};

namespace detail {
template <class D>
struct IsDescriptor : std::false_type {};
template <class F, Spec S, class T>
struct IsDescriptor<Descriptor<F, S, T>> : std::true_type {};
}  // namespace detail

// --- concepts drivers constrain their templates with -------------------------------------------------------

template <class D>
concept RegisterDescriptor = detail::IsDescriptor<std::remove_cvref_t<D>>::value;

template <class D>
concept Readable = RegisterDescriptor<D> && isReadable(std::remove_cvref_t<D>::access);

template <class D>
concept Writable = RegisterDescriptor<D> && isWritable(std::remove_cvref_t<D>::access);

template <class D>
concept CommandOnly = RegisterDescriptor<D> && std::remove_cvref_t<D>::access == Access::CommandOnly;

template <class D>
concept WriteOneToClear = RegisterDescriptor<D> && std::remove_cvref_t<D>::access == Access::ReadWrite1Clear;

template <class D>
concept ConfigUpdateOnly = RegisterDescriptor<D> && std::remove_cvref_t<D>::access == Access::ConfigUpdate;

// D's address as the code a bus carries: an 8-bit direct/SBS command or MAC code, a 16-bit subcommand,
// data-memory or register address. A compile error where the address does not fit, so drivers never
// truncate an address silently.
template <RegisterDescriptor D>
constexpr std::uint8_t code8(D) {
  static_assert(std::remove_cvref_t<D>::address <= 0xFF, "not an 8-bit code");
  return static_cast<std::uint8_t>(std::remove_cvref_t<D>::address);
}

template <RegisterDescriptor D>
constexpr std::uint16_t code16(D) {
  static_assert(std::remove_cvref_t<D>::address <= 0xFFFF, "not a 16-bit code");
  return static_cast<std::uint16_t>(std::remove_cvref_t<D>::address);
}

// A value of exactly D::size bytes (everything except variable-length blocks).
template <class D>
concept FixedSize = RegisterDescriptor<D> && !std::remove_cvref_t<D>::spec.variable;

template <class D>
concept VariableSize = RegisterDescriptor<D> && std::remove_cvref_t<D>::spec.variable;

// --- typed conversion between wire bytes and values
// ---------------------------------------------------------

// Decodes exactly D::size wire bytes (in D's byte order) into D's value type.
//   std::array<std::uint8_t, 2> wire{0x74, 0x0E};
//   std::int16_t mv = decode(bq769x2::cmd::Cell1Voltage, wire);   // 3700
template <Readable D>
requires FixedSize<D>
constexpr typename D::value_type decode(D, std::span<const std::uint8_t, D::size> bytes) {
  return detail::Codec<typename D::value_type>::load(bytes.data(), D::order);
}

// Decodes a variable-length block: copies min(bytes.size(), capacity) bytes.
template <Readable D>
requires VariableSize<D>
constexpr typename D::value_type decode(D, std::span<const std::uint8_t> bytes) {
  typename D::value_type v{};
  const std::size_t n = bytes.size() < v.data.size() ? bytes.size() : v.data.size();
  for (std::size_t i = 0; i < n; ++i)
    v.data[i] = bytes[i];
  v.length = static_cast<std::uint8_t>(n);
  return v;
}

// Encodes a value into exactly D::size wire bytes.
template <Writable D>
requires FixedSize<D>
constexpr void encode(D, const typename D::value_type& value, std::span<std::uint8_t, D::size> out) {
  detail::Codec<typename D::value_type>::store(out.data(), value, D::order);
}

// Same, returning the bytes:  auto wire = encode(bq769x2::dm::EnabledProtectionsA, bits::...);
template <Writable D>
requires FixedSize<D>
constexpr std::array<std::uint8_t, D::size> encode(D d, const typename D::value_type& value) {
  std::array<std::uint8_t, D::size> out{};
  encode(d, value, std::span<std::uint8_t, D::size>{out});
  return out;
}

// Encodes a variable-length block; returns the number of bytes written (at most out.size()).
template <Writable D>
requires VariableSize<D>
constexpr std::size_t encode(D, const typename D::value_type& value, std::span<std::uint8_t> out) {
  const std::size_t n = value.length < out.size() ? value.length : out.size();
  for (std::size_t i = 0; i < n; ++i)
    out[i] = value.data[i];
  return n;
}

// --- scale and plausibility --------------------------------------------------------------------------------

// Converts a raw integer reading into units of (D::unit / perUnit), rounded to nearest, exactly:
//   toUnits(bq79616::val::Vcell1, raw)          -> microvolts
//   toUnits(bq769x2::cmd::IntTemperature, r, 10) -> tenths of a kelvin (the raw value itself)
// Uses 64-bit integers only; |raw * num * perUnit| must stay below 2^63.
template <RegisterDescriptor D>
constexpr std::int64_t toUnits(D, std::int64_t raw, std::int64_t perUnit = 1) {
  const std::int64_t n = raw * D::scale.num * perUnit;
  const std::int64_t half = D::scale.den / 2;
  return (n >= 0 ? n + half : n - half) / D::scale.den;
}

// True when an integer reading lies within the TRM min..max (bounds the TRM leaves open always pass).
// The BQ4050 driver uses this on SBS values as a plausibility filter.
template <RegisterDescriptor D>
requires std::integral<typename D::value_type>
constexpr bool inRange(D, typename D::value_type value) {
  const auto v = static_cast<std::int64_t>(value);
  return (!D::hasMin || v >= D::spec.min) && (!D::hasMax || v <= D::spec.max);
}

}  // namespace fw::regmap
