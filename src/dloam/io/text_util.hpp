// Strict parsing helpers shared by the text formats (calib, poses, times, PCD, PLY headers).
// Internal to dloam_io.
#pragma once

#include <Eigen/Core>
#include <string>
#include <string_view>
#include <vector>

#include "dloam/core/types.hpp"

namespace dloam::io::detail {

/// Throws InputError "<path>: <what>".
[[noreturn]] void fail(const std::string& path, const std::string& what);
/// Throws InputError "<path>:<line>: <what>" (1-based line, like a compiler).
[[noreturn]] void fail_at(const std::string& path, std::size_t line, const std::string& what);

/// The lines of a text (without '\n' / '\r').
std::vector<std::string> split_lines(const std::string& text);

/// Farthest a point may lie from the sensor (m): beyond it a value is no LiDAR return (a wrong
/// unit or record layout), and voxel keys of any accepted leaf size stay in range.
inline constexpr double kMaxPointDistance = 1e6;
/// Throws InputError "<path>: point <i> ... farther than 1e6 m" when a coordinate exceeds it.
void check_point_distance(const std::string& path, std::size_t i, const Vec3& p);

/// True for lines that carry no data: empty, only spaces, or starting with '#'.
bool is_blank_or_comment(std::string_view line);

/// Whitespace-separated tokens.
std::vector<std::string_view> split(std::string_view text);

/// Parses every token of `text` as a double. Returns false (and leaves a description of the
/// first bad token in `error`) when a token is not a number, or is NaN/Inf unless allowed.
bool parse_doubles(std::string_view text, std::vector<double>& out, std::string& error,
                   bool allow_non_finite = false);

/// A non-negative integer token; throws "<path>:<line>: ..." otherwise (line 0: no line).
std::size_t parse_count(const std::string& path, std::size_t line, std::string_view token);

/// Pose from 12 row-major values of a 3x4 matrix [R | t].
Pose pose_from_row_major(const double* v);
/// Largest entry of |R^T R - I|, and det(R); used to reject non-rotations.
double orthonormality_error(const Eigen::Matrix3d& R);

/// "%.9e"-style number for text writers (round-trips floats, readable).
std::string format_number(double v);

}  // namespace dloam::io::detail
