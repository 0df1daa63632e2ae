#include "solvers/Checkpoint.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_XMLParameterListCoreHelpers.hpp>
#include <Teuchos_XMLParameterListHelpers.hpp>
#include <fcntl.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/Collective.hpp"

#ifndef IMPM_VERSION
#define IMPM_VERSION "unknown"
#endif

namespace impm {

namespace fs = std::filesystem;
using Teuchos::ParameterList;

namespace {

constexpr char kMagic[8] = {'I', 'M', 'P', 'M', 'C', 'K', 'P', 'T'};
constexpr char kEndMagic[8] = {'I', 'M', 'P', 'M', 'E', 'N', 'D', '.'};

std::string rankFileName(int rank) {
  char name[32];
  std::snprintf(name, sizeof name, "rank_%05d.bin", rank);
  return name;
}

// The deck's entries without validators or documentation, so that its XML reads back as plain values.
void plainCopy(const ParameterList& from, ParameterList& to) {
  for (auto it = from.begin(); it != from.end(); ++it) {
    const std::string& name = from.name(it);
    const Teuchos::ParameterEntry& e = from.entry(it);
    if (e.isList())
      plainCopy(from.sublist(name), to.sublist(name));
    else {
      Teuchos::ParameterEntry value;
      value.setAnyValue(e.getAny(false));
      to.setEntry(name, value);
    }
  }
}

// Through XML and back: the form in which the header holds the deck, for comparing the two.
ParameterList normalized(const ParameterList& deck) {
  std::ostringstream xml;
  Teuchos::writeParameterListToXmlOStream(deck, xml);
  return *Teuchos::getParametersFromXmlString(xml.str());
}

std::string valueText(const Teuchos::ParameterEntry& e) {
  std::ostringstream os;
  os << e.getAny(false);
  return os.str();
}

// The first entry in which two decks differ, described; empty when they are the same.
std::string firstDifference(const ParameterList& there, const ParameterList& here, const std::string& path) {
  for (auto it = here.begin(); it != here.end(); ++it) {
    const std::string& name = here.name(it);
    const std::string key = path + name;
    const Teuchos::ParameterEntry& h = here.entry(it);
    const Teuchos::ParameterEntry* t = there.getEntryPtr(name);
    if (!t) return "'" + key + "' is in this deck and not in the checkpoint's";
    if (h.isList() != t->isList()) return "'" + key + "' is a sublist in one deck and a value in the other";
    if (h.isList()) {
      const std::string d = firstDifference(there.sublist(name), here.sublist(name), key + "/");
      if (!d.empty()) return d;
    } else if (h.getAny(false).typeName() != t->getAny(false).typeName() || valueText(h) != valueText(*t)) {
      return "'" + key + "' is " + valueText(*t) + " in the checkpoint's deck and " + valueText(h) + " here";
    }
  }
  for (auto it = there.begin(); it != there.end(); ++it)
    if (!here.isParameter(there.name(it)))
      return "'" + path + there.name(it) + "' is in the checkpoint's deck and not in this one";
  return "";
}

// --- the rank file: little helpers over a byte string ---
template <class T>
void put(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

struct Cursor {
  const std::vector<char>& bytes;
  const std::string& path;
  size_t at = 0;
  void need(size_t n) const {
    if (at + n > bytes.size())
      throw CheckpointError("checkpoint file '" + path + "' is truncated or corrupt (it ends at byte " +
                            std::to_string(bytes.size()) + " inside its data)");
  }
  template <class T>
  T get() {
    need(sizeof(T));
    T value;
    std::memcpy(&value, bytes.data() + at, sizeof(T));
    at += sizeof(T);
    return value;
  }
  void getDoubles(double* to, size_t n) {
    need(n * sizeof(double));
    std::memcpy(to, bytes.data() + at, n * sizeof(double));
    at += n * sizeof(double);
  }
};

struct RankFile {
  int64_t step = 0;
  double time = 0;
  int32_t dim = 0, width = 0;
  int64_t count = 0;
  std::vector<double> rows;  // count x width
  NamedArrays arrays;
};

// Flushes a file or a directory (its entries: a new name, a rename) to the disk, so that a power
// loss after the checkpoint's rename cannot leave a renamed directory with an empty header.
void syncToDisk(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  const bool synced = fd >= 0 && ::fsync(fd) == 0;
  if (fd >= 0) ::close(fd);
  if (!synced) throw std::runtime_error("cannot flush the checkpoint's '" + path + "' to disk");
}

long long writeRankFile(const std::string& path, const CheckpointContent& c, int rank, int ranks) {
  auto rows = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), c.particles);
  const int64_t count = rows.extent(0);
  const int32_t width = rows.extent(1);
  std::string out;
  out.append(kMagic, 8);
  put<int32_t>(out, kCheckpointFormatVersion);
  put<int32_t>(out, rank);
  put<int32_t>(out, ranks);
  put<int64_t>(out, c.step);
  put<double>(out, c.time);
  put<int32_t>(out, 0);  // (reserved)
  put<int32_t>(out, width);
  put<int64_t>(out, count);
  out.append(reinterpret_cast<const char*>(rows.data()), sizeof(double) * count * width);  // LayoutRight: rows
  put<int32_t>(out, (int32_t)c.state.size());
  for (const auto& [name, values] : c.state) {
    put<int32_t>(out, (int32_t)name.size());
    out.append(name);
    put<int64_t>(out, (int64_t)values.size());
    out.append(reinterpret_cast<const char*>(values.data()), sizeof(double) * values.size());
  }
  out.append(kEndMagic, 8);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw std::runtime_error("cannot write the checkpoint file " + path);
  const bool written =
      std::fwrite(out.data(), 1, out.size(), f) == out.size() && std::fflush(f) == 0 && ::fsync(fileno(f)) == 0;
  if (std::fclose(f) != 0 || !written) throw std::runtime_error("cannot write the checkpoint file " + path);
  return (long long)out.size();
}

RankFile readRankFile(const std::string& path, int dim, int width) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CheckpointError("cannot read the checkpoint file '" + path + "'");
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Cursor c{bytes, path};
  c.need(8);
  if (std::memcmp(bytes.data(), kMagic, 8) != 0) throw CheckpointError("'" + path + "' is not an impm checkpoint file");
  c.at = 8;
  const int32_t version = c.get<int32_t>();
  if (version != kCheckpointFormatVersion)
    throw CheckpointError("checkpoint file '" + path + "' has format version " + std::to_string(version) +
                          "; this impm reads version " + std::to_string(kCheckpointFormatVersion));
  RankFile f;
  c.get<int32_t>();  // rank
  c.get<int32_t>();  // ranks
  f.step = c.get<int64_t>();
  f.time = c.get<double>();
  c.get<int32_t>();
  f.width = c.get<int32_t>();
  f.count = c.get<int64_t>();
  if (f.width != width)
    throw CheckpointError("checkpoint file '" + path + "' holds " + std::to_string(f.width) +
                          " values per particle; this deck's particles have " + std::to_string(width));
  if (f.count < 0) throw CheckpointError("checkpoint file '" + path + "' is corrupt (negative particle count)");
  c.need(size_t(f.count) * width * sizeof(double));
  f.rows.resize(size_t(f.count) * width);
  c.getDoubles(f.rows.data(), f.rows.size());
  const int32_t arrays = c.get<int32_t>();
  for (int32_t k = 0; k < arrays; ++k) {
    const int32_t length = c.get<int32_t>();
    if (length < 0) throw CheckpointError("checkpoint file '" + path + "' is corrupt (an array name)");
    c.need(length);
    std::string name(bytes.data() + c.at, length);
    c.at += length;
    const int64_t n = c.get<int64_t>();
    if (n < 0) throw CheckpointError("checkpoint file '" + path + "' is corrupt (an array size)");
    c.need(size_t(n) * sizeof(double));
    std::vector<double>& values = f.arrays[name];
    values.resize(n);
    c.getDoubles(values.data(), n);
  }
  c.need(8);
  if (std::memcmp(bytes.data() + c.at, kEndMagic, 8) != 0 || c.at + 8 != bytes.size())
    throw CheckpointError("checkpoint file '" + path + "' is corrupt (no end marker where its data ends)");
  (void)dim;
  return f;
}

}  // namespace

std::string impmVersion() { return IMPM_VERSION; }

ParameterList checkpointedDeck(const ParameterList& deck) {
  ParameterList plain;
  plainCopy(deck, plain);
  plain.remove("Output", false);
  plain.remove("Decomposition", false);  // how ranks split the grid: the restart may use another
  if (plain.isSublist("Problem")) plain.sublist("Problem").remove("Output Directory", false);
  if (plain.isSublist("Integrator")) plain.sublist("Integrator").remove("Number of Steps", false);
  return plain;
}

void writeCheckpoint(const std::string& outputDir, const ParameterList& deck, const CheckpointContent& mine,
                     const Teuchos::RCP<const Teuchos::Comm<int>>& comm) {
  const int rank = comm->getRank(), ranks = comm->getSize();
  char stem[48];
  std::snprintf(stem, sizeof stem, "checkpoint_%09d", mine.step);
  const std::string finalDir = outputDir + "/" + stem, tmpDir = finalDir + ".tmp";
  rethrowOnEveryRank(*comm, rank == 0, [&] {
    fs::remove_all(tmpDir);
    fs::create_directories(tmpDir);
  });
  long long bytes = 0;
  rethrowOnEveryRank(*comm, true, [&] { bytes = writeRankFile(tmpDir + "/" + rankFileName(rank), mine, rank, ranks); });
  std::vector<long long> mySize(ranks, 0), sizes(ranks, 0);
  mySize[rank] = bytes;
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, ranks, mySize.data(), sizes.data());
  long long localCount = mine.particles.extent(0), count = 0;
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, localCount, Teuchos::outArg(count));
  rethrowOnEveryRank(*comm, rank == 0, [&] {
    ParameterList header("impm checkpoint");
    header.set("Format Version", kCheckpointFormatVersion);
    header.set("impm Version", impmVersion());
    header.set("Step", mine.step);
    char time[40];
    std::snprintf(time, sizeof time, "%.17g", mine.time);
    header.set("Time", std::string(time));
    header.set("Ranks", ranks);
    header.set("Particles", std::to_string(count));
    ParameterList& files = header.sublist("Rank File Bytes");
    for (int r = 0; r < ranks; ++r) files.set(rankFileName(r), std::to_string(sizes[r]));
    header.sublist("Deck").setParameters(checkpointedDeck(deck));
    Teuchos::writeParameterListToXmlFile(header, tmpDir + "/header.xml");
    syncToDisk(tmpDir + "/header.xml");
    syncToDisk(tmpDir);  // the rank files' and the header's names
    // Complete: make it the checkpoint. The link is replaced by rename (atomic), and only then
    // are the older checkpoints removed.
    if (fs::exists(finalDir)) fs::remove_all(finalDir);
    fs::rename(tmpDir, finalDir);
    const std::string link = outputDir + "/checkpoint", newLink = link + ".new";
    fs::remove(newLink);
    fs::create_directory_symlink(stem, newLink);
    fs::rename(newLink, link);
    syncToDisk(outputDir);  // both renames
    for (const auto& entry : fs::directory_iterator(outputDir)) {
      const std::string name = entry.path().filename().string();
      if (name.rfind("checkpoint_", 0) == 0 && name != stem) fs::remove_all(entry.path());
    }
  });
}

namespace {

// A field of header.xml, of the type of the last argument.
template <class T>
T headerField(const ParameterList& header, const std::string& where, const std::string& key, T) {
  if (!header.isType<T>(key))
    throw CheckpointError(where + "header.xml has no valid '" + key + "' (truncated or not a checkpoint header)");
  return header.get<T>(key);
}

// header.xml, checked: complete, of this format and impm version, written for this deck.
ParameterList readCheckpointHeader(const std::string& dir, const std::string& where, const ParameterList& deck) {
  const std::string headerPath = dir + "/header.xml";
  if (!fs::is_directory(dir)) throw CheckpointError(where + "no such directory");
  if (!fs::exists(headerPath)) throw CheckpointError(where + "not a complete impm checkpoint (no header.xml)");
  ParameterList header;
  try {
    header = *Teuchos::getParametersFromXmlFile(headerPath);
  } catch (const std::exception&) {
    throw CheckpointError(where + "header.xml cannot be read (truncated or not a checkpoint header)");
  }
  const int format = headerField(header, where, "Format Version", 0);
  if (format != kCheckpointFormatVersion)
    throw CheckpointError(where + "checkpoint format version " + std::to_string(format) + "; this impm reads version " +
                          std::to_string(kCheckpointFormatVersion));
  const std::string version = headerField(header, where, "impm Version", std::string());
  if (version != impmVersion())
    throw CheckpointError(where + "written by impm version '" + version + "'; this is impm version '" + impmVersion() +
                          "'");
  if (!header.isSublist("Deck") || !header.isSublist("Rank File Bytes"))
    throw CheckpointError(where + "header.xml has no Deck or Rank File Bytes (truncated or not a checkpoint header)");
  const std::string difference = firstDifference(header.sublist("Deck"), normalized(checkpointedDeck(deck)), "");
  if (!difference.empty()) throw CheckpointError(where + "written for another deck: " + difference);
  return header;
}

// Every rank file whole (its size as the header says) before any is read.
void checkRankFileSizes(const std::string& dir, const std::string& where, const ParameterList& header, int writers) {
  const ParameterList& sizes = header.sublist("Rank File Bytes");
  for (int r = 0; r < writers; ++r) {
    const std::string name = rankFileName(r), path = dir + "/" + name;
    if (!sizes.isType<std::string>(name)) throw CheckpointError(where + "header.xml does not list " + name);
    const long long expected = std::stoll(sizes.get<std::string>(name));
    std::error_code ec;
    const auto actual = fs::file_size(path, ec);
    if (ec) throw CheckpointError(where + name + " is missing");
    if ((long long)actual != expected)
      throw CheckpointError(where + name + " is truncated or corrupt: " + std::to_string(actual) +
                            " bytes, header.xml says " + std::to_string(expected));
  }
}

}  // namespace

CheckpointContent readCheckpoint(const std::string& dir, const ParameterList& deck, int width, int dim,
                                 const std::function<bool(const double*)>& keep,
                                 const Teuchos::RCP<const Teuchos::Comm<int>>& comm) {
  const int rank = comm->getRank(), ranks = comm->getSize();
  CheckpointContent content;
  std::vector<double> kept;
  long long expectedParticles = 0;
  rethrowOnEveryRank(*comm, true, [&] {
    const std::string where = "--restart '" + dir + "': ";
    const ParameterList header = readCheckpointHeader(dir, where, deck);
    content.step = headerField(header, where, "Step", 0);
    content.time = std::stod(headerField(header, where, "Time", std::string()));
    const int writers = headerField(header, where, "Ranks", 0);
    const long long particles = std::stoll(headerField(header, where, "Particles", std::string()));
    checkRankFileSizes(dir, where, header, writers);
    // Same rank count: this rank's own file, its particles in their order. Otherwise every file,
    // keeping the particles of this rank's cells (and the per-rank arrays of all).
    const bool same = writers == ranks;
    for (int r = same ? rank : 0; r < (same ? rank + 1 : writers); ++r) {
      RankFile f = readRankFile(dir + "/" + rankFileName(r), dim, width);
      if (f.step != content.step)
        throw CheckpointError(where + rankFileName(r) + " is of step " + std::to_string(f.step) +
                              ", header.xml of step " + std::to_string(content.step));
      auto mine = [&](int64_t p) {
        double x[3] = {0, 0, 0};
        for (int d = 0; d < dim; ++d) x[d] = f.rows[size_t(p) * width + ParticleSet::packedPositionColumn(d)];
        return keep(x);
      };
      for (int64_t p = 0; p < f.count; ++p)
        if (same || mine(p))
          kept.insert(kept.end(), f.rows.begin() + size_t(p) * width, f.rows.begin() + size_t(p + 1) * width);
      for (auto& [name, values] : f.arrays) {
        const bool perRank = name.rfind(kNodeArrayPrefix, 0) == 0;
        if (perRank)
          content.state[name].insert(content.state[name].end(), values.begin(), values.end());
        else if (r == (same ? rank : 0))
          content.state[name] = std::move(values);
      }
    }
    expectedParticles = particles;
  });
  // Every particle found a rank (a slab rule that lost some would be silent otherwise).
  long long mine = kept.size() / width, total = 0;
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, mine, Teuchos::outArg(total));
  rethrowOnEveryRank(*comm, rank == 0, [&] {
    if (total != expectedParticles)
      throw CheckpointError("--restart '" + dir + "': the ranks took " + std::to_string(total) +
                            " particles; header.xml lists " + std::to_string(expectedParticles));
  });
  const int n = kept.size() / width;
  content.particles = ParticleSet::Packed("restart_rows", n, width);
  auto h = Kokkos::create_mirror_view(content.particles);
  std::memcpy(h.data(), kept.data(), sizeof(double) * kept.size());
  Kokkos::deep_copy(content.particles, h);
  return content;
}

}  // namespace impm
