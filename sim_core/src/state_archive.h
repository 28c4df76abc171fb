// The serialised form of a world's state: one field list per type (`archive(ar, value)`)
// serves writing, hashing and reading, so no field can be saved but forgotten by the hash.
// Native byte order and layout: a snapshot is read back by the same build.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace macsim::detail {

template <class T>
struct is_std_vector : std::false_type {};
template <class T, class A>
struct is_std_vector<std::vector<T, A>> : std::true_type {};
template <class T>
struct is_std_array : std::false_type {};
template <class T, std::size_t N>
struct is_std_array<std::array<T, N>> : std::true_type {};
template <class T>
struct is_std_pair : std::false_type {};
template <class A, class B>
struct is_std_pair<std::pair<A, B>> : std::true_type {};
template <class T>
struct is_std_optional : std::false_type {};
template <class T>
struct is_std_optional<std::optional<T>> : std::true_type {};

/// Numbers, enums and bools are stored as their bytes.
template <class T>
constexpr bool kStoredAsBytes = std::is_arithmetic_v<T> || std::is_enum_v<T>;
/// Fixed-size Eigen vectors and matrices: their coefficients, no padding.
template <class T>
constexpr bool kEigenFixed = [] {
  if constexpr (std::is_base_of_v<Eigen::MatrixBase<T>, T>) {
    static_assert(T::SizeAtCompileTime != Eigen::Dynamic, "only fixed-size Eigen types are stored");
    static_assert(sizeof(T) == sizeof(typename T::Scalar) * T::SizeAtCompileTime,
                  "a fixed-size Eigen type is its coefficients, no padding");
    return true;
  }
  return false;
}();
/// Elements a vector stores as one block of bytes.
template <class T>
constexpr bool kBlockElement = kStoredAsBytes<T> || kEigenFixed<T>;

// std::mt19937 is stored as its bytes (its words and index; no padding in libstdc++).
static_assert(std::is_trivially_copyable_v<std::mt19937>);
static_assert(sizeof(std::mt19937) == 625 * sizeof(std::mt19937::result_type));

/// Writes values to a sink (`ByteSink`: the bytes of a snapshot, which the state hash hashes).
template <class Sink>
class StateWriter {
 public:
  static constexpr bool kReading = false;
  template <class... T>
  void operator()(const T&... values) {
    (put(values), ...);
  }
  Sink& sink() { return sink_; }

 private:
  template <class T>
  void put(const T& value) {
    if constexpr (kStoredAsBytes<T>) {
      sink_.raw(&value, sizeof value);
    } else if constexpr (std::is_same_v<T, std::string>) {
      length(value.size());
      sink_.raw(value.data(), value.size());
    } else if constexpr (is_std_vector<T>::value) {
      length(value.size());
      if constexpr (kBlockElement<typename T::value_type>) {
        sink_.raw(value.data(), value.size() * sizeof(typename T::value_type));
      } else {
        for (const auto& each : value) put(each);
      }
    } else if constexpr (is_std_array<T>::value) {
      for (const auto& each : value) put(each);
    } else if constexpr (is_std_pair<T>::value) {
      put(value.first);
      put(value.second);
    } else if constexpr (is_std_optional<T>::value) {
      put(value.has_value());
      if (value) put(*value);
    } else if constexpr (kEigenFixed<T>) {
      sink_.raw(value.data(), sizeof(typename T::Scalar) * value.size());
    } else if constexpr (std::is_same_v<T, Eigen::Quaterniond>) {
      sink_.raw(value.coeffs().data(), 4 * sizeof(double));
    } else if constexpr (std::is_same_v<T, std::mt19937>) {
      sink_.raw(&value, sizeof value);
    } else {
      archive(*this, const_cast<T&>(value));  // writing never changes the value
    }
  }
  void length(std::size_t n) {
    const uint64_t n64 = n;
    sink_.raw(&n64, sizeof n64);
  }
  Sink sink_;
};

/// The bytes of a snapshot, appended into a buffer that only ever grows (clear() keeps it).
class ByteSink {
 public:
  void raw(const void* data, std::size_t size) {
    if (size == 0) return;
    if (used_ + size > buffer_.size()) buffer_.resize(std::max(2 * buffer_.size(), used_ + size));
    std::memcpy(buffer_.data() + used_, data, size);
    used_ += size;
  }
  void clear() { used_ = 0; }
  const uint8_t* data() const { return buffer_.data(); }
  std::size_t size() const { return used_; }

 private:
  std::vector<uint8_t> buffer_;
  std::size_t used_ = 0;
};

/// Counts the bytes written to it: the size a value's bytes will take, found before writing them.
class SizeSink {
 public:
  void raw(const void*, std::size_t size) { size_ += size; }
  std::size_t size() const { return size_; }

 private:
  std::size_t size_ = 0;
};

/// Appends the bytes to a vector reserved to their size beforehand: one allocation, no fill.
class VectorSink {
 public:
  void reserve(std::size_t size) { bytes_.reserve(size); }
  void raw(const void* data, std::size_t size) {
    const auto* from = static_cast<const uint8_t*>(data);
    bytes_.insert(bytes_.end(), from, from + size);
  }
  std::vector<uint8_t> take() { return std::move(bytes_); }

 private:
  std::vector<uint8_t> bytes_;
};

/// Reads values back in the order they were written; throws std::runtime_error when the bytes
/// run out or a length is impossible (a damaged snapshot, or one of another build).
class StateReader {
 public:
  static constexpr bool kReading = true;
  explicit StateReader(const std::vector<uint8_t>& bytes) : bytes_(bytes) {}
  template <class... T>
  void operator()(T&... values) {
    (get(values), ...);
  }
  bool at_end() const { return at_ == bytes_.size(); }

 private:
  template <class T>
  void get(T& value) {
    if constexpr (std::is_same_v<T, bool>) {
      uint8_t byte = 0;  // a bool is 0 or 1: anything else is damage, not a bool
      raw(&byte, 1);
      if (byte > 1) throw std::runtime_error("the snapshot has a damaged flag");
      value = byte == 1;
    } else if constexpr (kStoredAsBytes<T>) {
      raw(&value, sizeof value);
    } else if constexpr (std::is_same_v<T, std::string>) {
      value.resize(length(1));
      raw(value.data(), value.size());
    } else if constexpr (is_std_vector<T>::value) {
      using E = typename T::value_type;
      if constexpr (kBlockElement<E>) {
        value.resize(length(sizeof(E)));
        raw(value.data(), value.size() * sizeof(E));
      } else {
        value.clear();
        value.resize(length(1));
        for (auto& each : value) get(each);
      }
    } else if constexpr (is_std_array<T>::value) {
      for (auto& each : value) get(each);
    } else if constexpr (is_std_pair<T>::value) {
      get(value.first);
      get(value.second);
    } else if constexpr (is_std_optional<T>::value) {
      bool present = false;
      get(present);
      if (present) {
        value.emplace();
        get(*value);
      } else {
        value.reset();
      }
    } else if constexpr (kEigenFixed<T>) {
      raw(value.data(), sizeof(typename T::Scalar) * value.size());
    } else if constexpr (std::is_same_v<T, Eigen::Quaterniond>) {
      raw(value.coeffs().data(), 4 * sizeof(double));
    } else if constexpr (std::is_same_v<T, std::mt19937>) {
      raw(&value, sizeof value);
    } else {
      archive(*this, value);
    }
  }
  void raw(void* data, std::size_t size) {
    if (size == 0) return;  // an empty vector's data() may be null
    if (size > bytes_.size() - at_) throw std::runtime_error("the snapshot is truncated");
    std::memcpy(data, bytes_.data() + at_, size);
    at_ += size;
  }
  /// A stored element count, checked against the bytes left (each element takes `min_size`).
  std::size_t length(std::size_t min_size) {
    uint64_t n = 0;
    raw(&n, sizeof n);
    if (n > (bytes_.size() - at_) / min_size) {
      throw std::runtime_error("the snapshot has an impossible length");
    }
    return static_cast<std::size_t>(n);
  }
  const std::vector<uint8_t>& bytes_;
  std::size_t at_ = 0;
};

/// Whether every number is finite and within +-limit: what angles, times and positions read
/// back from a snapshot may be before a robot converts them (to encoder ticks, say).
inline bool all_plausible(std::initializer_list<double> values, double limit = 1e12) {
  for (double v : values) {
    if (!(std::abs(v) <= limit)) return false;  // NaN fails too
  }
  return true;
}

/// Whether a generator read back from a snapshot can run: its position within its 624 words,
/// words of 32 bits, not all zero (else it draws zeros, or numbers out of its range, for ever,
/// and a Gaussian drawn by rejection never ends).
inline bool plausible_generator(const std::mt19937& generator) {
  std::array<std::mt19937::result_type, 625> words;  // the state, then the position
  std::memcpy(words.data(), &generator, sizeof generator);
  if (words[624] > 624) return false;
  bool any = (words[0] & 0x80000000u) != 0;  // of the first word only its top bit counts
  for (std::size_t i = 0; i < 624; ++i) {
    if (words[i] > 0xffffffffu) return false;
    if (i > 0 && words[i] != 0) any = true;
  }
  return any;
}

/// `value`'s bytes by its field list (a robot's part of the state, say): counted first, then
/// written once into a vector of that size (a robot's clouds make it a megabyte, taken at every
/// state hash: growing a buffer to it cost more than the rest of the hash).
template <class T>
std::vector<uint8_t> to_bytes(const T& value) {
  StateWriter<SizeSink> counter;
  counter(value);
  StateWriter<VectorSink> writer;
  writer.sink().reserve(counter.sink().size());
  writer(value);
  return writer.sink().take();
}

/// The value to_bytes() wrote; throws std::runtime_error on damaged or trailing bytes.
template <class T>
T from_bytes(const std::vector<uint8_t>& bytes) {
  T value;
  StateReader reader(bytes);
  reader(value);
  if (!reader.at_end()) throw std::runtime_error("the snapshot has bytes after its end");
  return value;
}

}  // namespace macsim::detail
