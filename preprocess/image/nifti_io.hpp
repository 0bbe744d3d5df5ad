#pragma once
// NIfTI input and output through nifti_clib's libnifti2 (reads NIfTI-1 and -2,
// .nii and .nii.gz). Geometry: the sform is used when its code is > 0, else the
// qform when its code is > 0, else a diagonal affine from pixdim. Spatial units
// (xyz_units) are converted to metres; an unset unit is taken as millimetres
// (the NIfTI convention of most scanners and tools) and reported in the notes.
#include <filesystem>
#include <string>
#include <vector>

#include "preprocess/image/image.hpp"

namespace adamss::preprocess {

/// What the reader noticed while reading (unit assumptions, orientation source, type).
struct NiftiNotes {
  std::string datatype;       ///< e.g. "uint8", "float32"
  std::string affine_source;  ///< "sform", "qform" or "pixdim"
  std::string units;          ///< e.g. "mm", "m", "um", "unknown (mm assumed)"
  int nifti_version = 1;      ///< 1 or 2
  std::vector<std::string> warnings;
};

/// Reads a 3-D label image. Accepted types: uint8, int8, int16, uint16, int32,
/// uint32 (values must fit int32), float32/float64 only if every value is integral.
/// Throws adamss::InputError naming the file for: a missing or truncated file, a
/// non-3-D image (a 4th dimension of size 1 is accepted), another type, a
/// non-integral float, NaN/Inf in the affine, zero or non-finite spacing.
///
/// A header with scl_slope/scl_inter other than "none" (slope 0, or slope 1 with intercept 0)
/// would change the labels (intercept 1 makes the background label 0 into 1, and the whole
/// background would be meshed). LabelScaling::kRefuse (the default) makes such a file an
/// InputError that says so; kApply applies the scaling and adds a warning to `notes`.
enum class LabelScaling { kRefuse, kApply };
LabelImage read_label_image(const std::filesystem::path& path, NiftiNotes* notes = nullptr,
                            LabelScaling scaling = LabelScaling::kRefuse);

/// Reads a 3-component vector image (fibre/sheet field): dims (nx, ny, nz, 1, 3)
/// as NIfTI stores vectors (intent VECTOR), or (nx, ny, nz, 3). float32 or float64.
VectorImage read_vector_image(const std::filesystem::path& path, NiftiNotes* notes = nullptr);

/// Reads a 3-D scalar image (a per-voxel field for `mesh --cell-field`): any numeric type
/// (uint8 .. uint64, int8 .. int64, float32, float64), scl_slope/scl_inter applied, NaN
/// kept. Same geometry rules and errors as read_label_image.
ScalarImage read_scalar_image(const std::filesystem::path& path, NiftiNotes* notes = nullptr);

/// Writes a scalar image as NIfTI-1 float32 (values rounded to float).
void write_scalar_image(const std::filesystem::path& path, const ScalarImage& image);

/// Writes a label image as NIfTI-1 (.nii or .nii.gz by extension), uint8 when all
/// labels fit, else int16 or int32; sform and qform both set from the affine,
/// units millimetres.
void write_label_image(const std::filesystem::path& path, const LabelImage& image);

/// Writes a vector image as NIfTI-1 float32 with dims (nx, ny, nz, 1, 3), intent VECTOR.
void write_vector_image(const std::filesystem::path& path, const VectorImage& image);

}  // namespace adamss::preprocess
