#pragma once
// HDF5 checkpoints of a DEM model (docs/architecture.md, "Checkpoints and
// restart"): the complete dynamic state — particles, walls, every
// contact group with its per-contact arrays and law state, the stepping
// state (step, time, time step, detection reference positions), the energy
// baseline and the crack records — so that a restarted run continues
// bit for bit as if it had never stopped.
//
// The model's structure is not rebuilt from the file: the caller builds the
// model from its input file (same law groups with the same parameters), then
// restores the state with read_checkpoint, which checks that the law groups
// and their parameters match. Metadata strings (e.g. the .prm text) travel
// with the checkpoint for the caller to compare.
//
// Every dataset carries a Fletcher32 checksum, verified on reading: a
// damaged file is refused naming the dataset. Format version 5: the named
// state of the objects around the model (dem/io/state_archive.h) is stored
// as datasets /state/<name>, one per entry.
//
// File layout (HDF5, one file): datasets format/version/dim on the root;
// /metadata (keys, values); /state (names, one dataset per name);
// /model (scalars); /particles; /walls;
// /groups/<g> (law, params, per-contact arrays, state); /cracks. Vector
// arrays are n x dim datasets.
#include "dem/engine/model.h"
#include "dem/io/state_archive.h"

#include <map>
#include <string>

namespace demfem::dem
{
  /// Writes the state of `model` to `path` atomically: the file is written
  /// as `path.tmp`, flushed and fsync'ed, the existing `path` (if any) is
  /// kept as `path.prev`, and the new file is renamed over `path`. On any
  /// failure the existing files are untouched and std::runtime_error is
  /// thrown naming the file.
  /// `state`: named arrays of the caller's objects (StateArchive::saving).
  template <int dim>
  void write_checkpoint(const Model<dim> &model, const std::string &path,
                        const std::map<std::string, std::string> &metadata,
                        const NamedArrays                        &state = {});

  /// Restores the state saved in `path` into `model`, which must already
  /// hold the same contact-law groups (same count, law names and parameters,
  /// in the same order) as the checkpointed model. A mismatch, a wrong
  /// dimension or a damaged/missing file throws InputError naming the file
  /// and what differs; the model is then left unchanged. The metadata
  /// written with the checkpoint is returned in `*metadata` (if non-null).
  /// The named state written with it is returned in `*state` (if
  /// non-null), for StateArchive::loading.
  template <int dim>
  void read_checkpoint(Model<dim> &model, const std::string &path,
                       std::map<std::string, std::string> *metadata,
                       NamedArrays                        *state = nullptr);

  /// Reads every dataset of a checkpoint once, so that a damaged file is
  /// refused before a model is built for it: InputError naming the file and
  /// the dataset whose Fletcher32 checksum fails (or the damaged structure).
  void verify_checkpoint(const std::string &path);

  /// Only the metadata and the dimension of a checkpoint (e.g. to compare
  /// the input file before building the model).
  std::map<std::string, std::string> read_checkpoint_metadata(const std::string &path,
                                                              int *dim = nullptr);
} // namespace demfem::dem
