#pragma once
// H5MD 1.1 trajectory writer (doc/io.md), compiled with MARBLE_HAVE_HDF5.
//
// Layout: /h5md (version [1, 1], author, creator), /particles/atoms/box
// (dimension 3, boundary, edges as a [frames, 3, 3] time series) and
// /particles/atoms/{position, image, velocity, force, species, mass, id}, each
// with value [frames, N(, 3)], step [frames] and time [frames], extensible in
// frames. Row k of a frame is the particle with the k-th smallest id. Positions
// are folded into the box with their image counts (position + image * box_l is
// the unfolded position).
//
// SRD particles (feature SRD) go to /particles/srd (see H5mdFields::srd),
// rows by increasing SRD id.
//
// With MPI the file is opened with the MPI-IO driver on the System's
// communicator and written collectively: each rank writes its own local
// particles into their rows. Every call here is collective.
#include "system/System.hpp"

#include <memory>
#include <string>

namespace Marble::IO {

struct H5mdFields {
  bool position = true, image = true, velocity = true, force = true, species = true, mass = true,
       id = true, box = true, time = true, step = true;
  /** SRD solvent (feature SRD): its particles in their own group
   * /particles/srd/{position, velocity, species, id} (the subset of those
   * fields that is on; positions folded, no image), with /particles/srd/box
   * and step/time shared with /particles/atoms. Written if the System has an
   * SRD fluid with particles when the first frame is written. */
  bool srd = true;
};

class H5mdFile {
public:
  /** Create (truncate) @p path, or with @p append open an existing H5MD file
   * written by Marble and continue its time series (a missing file is
   * created). Appending needs the file's fields to be @p fields; frames keep
   * the file's number of particles. Throws Utils::RuntimeError if the file
   * cannot be created/opened or does not match. */
  H5mdFile(System const &system, std::string const &path, H5mdFields const &fields,
           std::string const &author, bool append = false);
  ~H5mdFile();
  H5mdFile(H5mdFile const &) = delete;
  H5mdFile &operator=(H5mdFile const &) = delete;

  /** Append the current state of @p system as one frame. The number of
   * particles is fixed by the first frame: a change throws Utils::RuntimeError. */
  void write(System const &system);
  void flush();
  /** Close the file; throws Utils::RuntimeError if the final write fails
   * (e.g. a full disk); the file is closed either way. */
  void close();
  bool is_open() const;
  long n_frames() const;
  /** Number of particles per frame (-1 before the first frame). */
  long n_particles() const;
  std::string const &path() const;

private:
  void write_frame(System const &system);
  void write_srd_frame(System const &system); // feature SRD
  struct Impl;
  std::unique_ptr<Impl> m;
};

} // namespace Marble::IO
