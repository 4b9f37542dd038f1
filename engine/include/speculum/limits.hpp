// Limits on what a file may ask of the tools, checked before anything is allocated, so that a
// hostile or corrupt file ends in exit 3 with a message naming the file and the numbers instead
// of a crash, a hang or an out-of-memory kill (issue 15). Each limit says why it has its value.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace speculum::limits {

// JSON nesting ([ and {) in a glTF, settings or camera-path file. tinygltf converts JSON values
// recursively and overflowed the 8 MiB main-thread stack at about 16,000 levels (14,000 still
// rendered); real files nest below 20. 512 leaves a factor of 30 under the crash on any stack.
inline constexpr int kMaxJsonDepth = 512;

// Equirect environment maps. 16384 a side is the largest the texture paths handle anywhere; the
// pixel cap (8192x4096 = 33.5 M) bounds the load at 33.5 M x 12 bytes x 2 copies (float file
// pixels and the texel array) = 805 MB of host memory and a 403 MB device buffer. A 21-byte
// header claiming 100000x100000 used to end in std::bad_alloc, 20000x10000 took 2.5 GB.
inline constexpr uint64_t kMaxEnvironmentSide = 16384;
inline constexpr uint64_t kMaxEnvironmentPixels = uint64_t(8192) * 4096;

// Scene geometry after the loader expands accessors into vertices (48 bytes each) and 32-bit
// indices, summed over every primitive. A 2 KB glTF that reuses one 1 M-vertex accessor in 48
// primitives expanded to 2.3 GB and took 7.4 GB of process memory before the driver crashed;
// 1 GiB is 22 M vertices, ten times the largest scene in the suite.
inline constexpr uint64_t kMaxSceneGeometryBytes = uint64_t(1) << 30;

// The share of the largest device-local heap the scene's vertex, index and texture data may use:
// the frame graph's transient targets, the environment cubes, probe arrays and the driver need
// the rest (lavapipe reports one 2 GiB heap; the gallery at 960x540 uses about 150 MB of it).
inline constexpr double kSceneHeapShare = 0.5;

// Files the tools read as text (glTF JSON, settings, camera paths): regular files only (a FIFO or
// /dev/zero would block or never end) and at most this size (the largest real one is ~200 KB).
inline constexpr uint64_t kMaxTextFileBytes = uint64_t(256) << 20;

// Throws Error(BadInput) naming `file` when `text` nests [ and { deeper than kMaxJsonDepth.
// Strings are skipped, so brackets inside them do not count. O(n), no allocation.
void checkJsonDepth(const std::string& text, const std::string& file);

// Reads a whole regular file for JSON parsing: exit 3 naming the file for a folder, a device, a
// missing or unreadable file, or one over kMaxTextFileBytes; then checkJsonDepth. `what` names the
// kind of file in messages ("settings file", "camera path").
std::string readJsonText(const std::filesystem::path& path, const std::string& what);

// "1.5 GiB" / "300.0 MiB": sizes in messages.
std::string bytesText(uint64_t bytes);

}  // namespace speculum::limits
