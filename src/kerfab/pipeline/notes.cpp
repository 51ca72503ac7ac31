#include "kerfab/pipeline/notes.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

namespace kerfab {
namespace {

/// A stream for one line, numbers to 4 significant digits.
struct Line : std::ostringstream {
  explicit Line(int precision = 4) { this->precision(precision); }
};

/// A size to pass to --size, rounded up to whole millimetres: as an integer, so that a large one
/// reads 12240, not 1.224e+04 (a line's precision is four digits).
long long whole_mm(double mm) { return static_cast<long long>(std::ceil(mm)); }

/// Sizes past this are no answer to a maker: the regions that would need them (creases, faces
/// folded back thinner than the sheets) need another remedy than size [mm].
constexpr double kLargestSize = 10000;

/// Borders a warning names by their two parts, at most [-].
constexpr std::size_t kBordersNamed = 6;

/// \p parts named after \p w, up to kBordersNamed of them ("3, 8, ...").
void name_parts(Line& w, const std::vector<int>& parts) {
  for (std::size_t k = 0; k < parts.size() && k < kBordersNamed; ++k)
    w << (k ? ", " : "") << parts[k];
  if (parts.size() > kBordersNamed) w << ", ...";
}

std::string summary_line(const std::string& what, const MeshSummary& s) {
  Line os;
  os << what << ": " << s.vertices << " vertices, " << s.faces << " faces (";
  for (std::size_t i = 0; i < s.face_sizes.size(); ++i)
    os << (i ? ", " : "") << s.face_sizes[i].second << "x" << s.face_sizes[i].first << "-gon";
  const Vec3 size = s.bbox.size();
  os << "), " << s.boundary_loops << " boundary loop(s), Euler characteristic "
     << s.euler_characteristic << ", bbox " << size.x() << " x " << size.y() << " x " << size.z()
     << " mm";
  return os.str();
}

}  // namespace

StageNotes notes(const LoadedInputs& loaded) {
  StageNotes n;
  auto mended = [&](const std::string& file, const MeshRepairs& r) {
    const auto say = [&](int count, const char* what) {
      if (count == 0) return;
      Line w;
      w << file << ": " << count << what << " (input." << file << "_repairs)";
      n.warnings.push_back(w.str());
    };
    say(r.vertices_welded,
        " vertices at the same point as another on a border were welded to it, joining the "
        "faces there");
    say(r.duplicate_faces, " faces repeating another face's corners were dropped");
    say(r.faces_turned,
        " faces turned the other way from their neighbours were turned round, each closed "
        "piece facing out");
  };
  mended("target", loaded.target_repairs);
  if (loaded.quad) mended("quad", loaded.quad_repairs);
  return n;
}

StageNotes notes(const PreparedInput& in) {
  StageNotes n;
  n.lines.push_back(summary_line("target", in.target_summary));
  Line os;
  if (in.quad_summary.faces == 0) {  // a triangle mesh alone: the quads stage meshes it
    n.lines.push_back("quads: none given; the quads stage makes them from the target");
    os << "scale " << in.scale;
  } else {
    n.lines.push_back(
        summary_line(in.quads_from_target ? "quads (from target)" : "quads", in.quad_summary));
    os << "scale " << in.scale << ", quad vertices to target: max " << in.quad_max_distance
       << " mm, mean " << in.quad_mean_distance << " mm";
  }
  n.lines.push_back(os.str());
  n.warnings = in.warnings;
  return n;
}

StageNotes notes(const QuadMeshResult& q) {
  StageNotes n;
  Line os;
  os << q.quads.n_faces() << " quads of " << q.size.size << " mm (" << q.size.reason << "; kerf "
     << q.size.kerf_size << " mm, fidelity " << q.size.fidelity_size << " mm), "
     << q.irregular_vertices << " irregular vertices, method: " << q.method;
  n.lines.push_back(os.str());
  // Quads asked smaller than the strips the material needs to bend here (the size rule's kerf
  // bound): their strips are too short for the cuts they need, and the resolve stage has a
  // region to mend for almost every one of them (bunny_closed at --quads 1500: 482 of 1672).
  if ((q.size.reason == "--quads" || q.size.reason == "--quad-size") &&
      q.size.size < 0.9 * q.size.kerf_size) {
    Line w(3);
    w << q.size.reason << " makes quads of " << q.size.size << " mm, narrower than the "
      << q.size.kerf_size << " mm strips this material needs to bend at this model's curvature "
      << "(docs/quad-meshing.md, Size): expect many critical regions, resolved by smaller parts "
      << "or left; --quad-size " << q.size.kerf_size << " (about "
      << static_cast<long>(std::lround(q.size.area / (q.size.kerf_size * q.size.kerf_size)))
      << " quads) or a larger --size avoids that";
    n.warnings.push_back(w.str());
  }
  if (q.method.rfind("triangles", 0) == 0) {  // the safe net: no lattice anywhere
    Line w;
    w << "quad mesh made without a lattice (" << q.method << "): " << q.irregular_vertices
      << " irregular vertices, so more strips; a quad mesh of your own (--quad) may do better";
    n.warnings.push_back(w.str());
  }
  return n;
}

StageNotes notes(const CoarsenResult& c) {
  StageNotes n;
  Line os;
  if (!c.changed()) {
    os << "quad mesh used as given (" << c.quads_before << " quads): ";
    if (c.narrow_before == 0)
      os << "its strips are wide enough everywhere for their bends";
    else
      os << 100 * c.narrow_before << "% of its cross edges have a row too narrow for its bend, "
         << "and no row there can go without its neighbours missing the target";
    n.lines.push_back(os.str());
    return n;
  }
  os << c.quads_before << " quads given, " << c.quads_after << " kept: ";
  if (c.levels_taken_back > 0)
    os << c.levels_taken_back << " level" << (c.levels_taken_back > 1 ? "s" : "")
       << " of subdivision taken back (each doubles every row's width), ";
  os << c.rows_collapsed << " rows collapsed where the strips beside them were too narrow to bend ("
     << c.rows_refused << " more could not go), cross edges with a row too narrow for its bend "
     << 100 * c.narrow_before << "% -> " << 100 * c.narrow_after
     << "%; the mesh used is model/quads.obj (--no-coarsen: as given)";
  n.lines.push_back(os.str());
  return n;
}

StageNotes notes_coarsen_skipped(const std::string& why) {
  StageNotes n;
  n.lines.push_back("quad mesh used as given: " + why);
  return n;
}

StageNotes notes(const BendingResult& b) {
  StageNotes n;
  Line os;
  os << b.bendable_count << " of " << b.bendable.size() << " edges bendable, objective "
     << b.objective << " (bound " << b.bound << ", " << to_string(b.status) << ", "
     << b.solve_seconds << " s), aligned " << 100.0 * b.aligned_fraction << "%";
  n.lines.push_back(os.str());
  if (b.status != PackingStatus::kOptimal) {
    Line w;
    w << "bending program not proven optimal (" << to_string(b.status) << "): objective "
      << b.objective << ", bound " << b.bound;
    n.warnings.push_back(w.str());
  }
  return n;
}

StageNotes notes(const Strips& s, const std::optional<RowBaseline>& baseline,
                 const StripsOptions& options) {
  StageNotes n;
  Line os;
  os << s.patches.size() << " strips from " << s.chains << " chains (" << s.closed_loops
     << " closed loops cut, " << s.split_borders << " split at folds > "
     << options.split_angle * 180 / M_PI << " deg); " << s.faces.size() << " sub-quads, "
     << s.vertices.size() << " vertices, " << s.t_junctions << " T-junction vertices";
  if (baseline)
    os << "; a naive one-strip-per-row layout would give " << baseline->strips << " ("
       << baseline->quad_rows << " quad rows)";
  n.lines.push_back(os.str());
  if (s.ray_fallbacks > 0)
    n.lines.push_back(std::to_string(s.ray_fallbacks) +
                      " vertices missed the target along their normal and went to the closest "
                      "point instead");
  return n;
}

StageNotes notes(const CuttablePatches& c, double diagonal) {
  StageNotes n;
  const Flattening& f = c.flattening;
  if (c.overlap_splits + c.distortion_splits + c.oversize_splits > 0)
    n.lines.push_back(
        std::to_string(c.overlap_splits) + " patch splits because a flat outline crossed itself, " +
        std::to_string(c.distortion_splits) + " because a strip flattened too distorted, " +
        std::to_string(c.oversize_splits) + " because a part was larger than the sheet; now " +
        std::to_string(c.strips.patches.size()) + " patches");
  int iterations = 0;
  for (const auto& p : f.patches) iterations = std::max(iterations, p.iterations);
  Line os;
  os << f.patches.size() << " patches flattened (at most " << iterations
     << " Gauss-Newton iterations, " << f.unconverged << " not converged); max angle error "
     << f.max_angle_error * 180 / M_PI << " deg, max border length error "
     << 100 * f.max_border_length_error_rel << "%, mating borders differ by at most "
     << 100 * f.max_mating_mismatch_rel << "% per piece, " << 100 * f.max_shared_border_mismatch_rel
     << "% per shared border";
  n.lines.push_back(os.str());
  if (c.deformation) {
    Line m;
    m << "3D strips deformed to the flat metric move by at most " << c.deformation->hausdorff
      << " mm (Hausdorff, " << 100 * c.deformation->hausdorff / diagonal << "% of diagonal)";
    n.lines.push_back(m.str());
  }
  if (f.inverted_quads > 0)
    n.warnings.push_back("flattening inverted " + std::to_string(f.inverted_quads) +
                         " quads (see flatten.patches in the report); those parts will not "
                         "fit as designed");
  if (f.non_simple_outlines > 0)
    n.warnings.push_back(std::to_string(f.non_simple_outlines) +
                         " flattened patches still overlap themselves in the plane after "
                         "splitting (see flatten.patches)");
  if (f.unconverged > 0)
    n.warnings.push_back(std::to_string(f.unconverged) +
                         " patches did not converge in the flattening iteration limit");
  return n;
}

StageNotes notes(const Joints& j, const JointOptions& options, double thickness,
                 const std::vector<int>& unresolved) {
  StageNotes n;
  int blocked = 0, shallow = 0;
  for (const auto& b : j.borders) blocked += b.blocked, shallow += b.shallow;
  Line os;
  // Paper has glue tabs, no teeth to count. Border length joined [mm]:
  const bool paper = thickness == 0;
  const double joined = paper ? j.glue_length : j.toothed_length;
  if (paper)
    os << j.glue_tabs << " glue tabs";
  else
    os << j.teeth - j.tabs << " box teeth and " << j.tabs << " dovetail tabs";
  os << " on " << j.borders.size() << " border pieces ("
     << 100 * (j.border_length > 0 ? joined / j.border_length : 0)
     << "% of the shared border length" << (paper ? " glued); " : "); ") << j.borders_without_joint
     << " border pieces without a joint (and " << j.stubs_joined_at_corners
     << " stubs held by the joints at their corners)";
  if (!paper)
    os << "; intervals without teeth: " << shallow << " too shallow (tip - slot < "
       << options.min_depth << " mm), " << blocked << " in collision regions";
  if (j.draft)
    os << " (a draft for the resolve stage: short borders between corners get their stub teeth "
          "in its final build)";
  n.lines.push_back(os.str());
  if (j.draft) return n;  // its warnings come with the final build
  // A border with nothing that locates its two parts or holds them while the glue sets is a
  // defect of the build: said, with where and why. (Paper with --glue-tab 0 asks for plain
  // borders.)
  const bool plain_asked = paper && options.glue_tab == 0;
  if (j.borders_without_joint > 0 && !plain_asked) {
    int left = 0, apart = 0, folded_back = 0, too_shallow = 0, too_short = 0, crowded = 0;
    double length = 0;  // [mm]
    std::vector<std::string> where;
    const auto fell = [&](int p) {
      return p >= 0 && p < static_cast<int>(j.parts.size()) && j.parts[p].repaired;
    };
    for (const BorderJoint& b : j.borders) {
      if (b.kind() != "none") continue;
      length += b.length;
      if (std::binary_search(unresolved.begin(), unresolved.end(), b.patches[0]) ||
          std::binary_search(unresolved.begin(), unresolved.end(), b.patches[1]))
        ++left;
      else if (fell(b.patches[0]) || fell(b.patches[1]))
        ++apart;
      else if (std::any_of(b.intervals.begin(), b.intervals.end(), [](const JointInterval& in) {
                 return std::abs(in.fold) > kFoldBackAngle;
               }))
        ++folded_back;
      else if (b.shallow > 0 && b.blocked == 0)
        ++too_shallow;
      else if (b.length < options.min_feature)
        ++too_short;
      else
        ++crowded;
      if (where.size() < kBordersNamed)
        where.push_back(std::to_string(b.patches[0]) + " and " + std::to_string(b.patches[1]));
    }
    Line w;
    w << j.borders_without_joint << " shared borders (" << length
      << " mm) have no joint: nothing locates their two parts or holds them while the glue sets "
         "(joints.borders, joint \"none\"); between parts ";
    for (std::size_t k = 0; k < where.size(); ++k) w << (k ? ", " : "") << where[k];
    if (j.borders_without_joint > static_cast<int>(where.size())) w << ", ...";
    w << ":";
    const char* sep = " ";
    if (left > 0) {
      w << sep << left
        << " beside a part left too small, narrow or distorted to handle "
           "(resolve.unresolved_parts; the resolve warning says what would make it hold, where "
           "known)";
      sep = "; ";
    }
    if (apart > 0) {
      w << sep << apart << " beside a part that fell apart when its joints were cut";
      sep = "; ";
    }
    if (folded_back > 0) {
      w << sep << folded_back
        << " folded back more than 150 deg, where the shape is thinner than two sheets and "
           "their mitres cut both parts back (a larger --size or a thinner --material)";
      sep = "; ";
    }
    if (too_shallow > 0) {
      w << sep << too_shallow << " folded too shallow for a tooth " << options.min_depth
        << " mm deep (--min-tooth-depth";
      if (options.tab_misfit == 0) w << "; dovetail tabs are off: --tab-misfit 0";
      w << ")";
      sep = "; ";
    }
    if (too_short > 0) {
      w << sep << too_short << " shorter than the smallest feature (" << options.min_feature
        << " mm), too short for any " << (paper ? "glue tab" : "tooth")
        << " (where the resolve stage cut a part across a neck that narrow, it is where the neck "
           "was)";
      sep = "; ";
    }
    if (crowded > 0)
      w << sep << crowded
        << (paper ? " with no room for a glue tab clear of the tabs beside them"
                  : " with no room for a tooth clear of the joints beside them");
    n.warnings.push_back(w.str());
  }
  if (!j.thin_neck_parts.empty()) {
    Line w;
    w << j.thin_neck_parts.size() << " parts narrow to a neck under " << options.min_feature
      << " mm between two of their pieces, where what hangs on it may break off or burn away "
         "(joints.thin_neck_parts): parts ";
    name_parts(w, j.thin_neck_parts);
    n.warnings.push_back(w.str());
  }
  if (!j.slit_parts.empty()) {
    Line w;
    w << j.slit_parts.size() << " parts keep a slit narrower than " << options.min_feature
      << " mm, a cut the laser cannot make cleanly, that the outline cleanup could not widen "
         "(where that would cut the part in two, or into a tooth beside it; joints.slit_parts): "
         "parts ";
    name_parts(w, j.slit_parts);
    n.warnings.push_back(w.str());
  }
  if (j.repaired_parts > 0) {
    Line w(3);
    w << j.repaired_parts
      << " parts fell apart into pieces when their joints were cut; only the largest piece of "
         "each is kept ("
      << j.lost_area << " mm^2 lost in all, the largest lost piece " << j.largest_lost_piece
      << " mm^2; joints.lost_area_mm2)";
    n.warnings.push_back(w.str());
  }
  return n;
}

std::string skipped_cuts_warning(int by_options, int planned, const KerfOptions& options,
                                 bool at_first) {
  const KerfOptions d;
  Line w(3);
  w << (at_first ? "at first, " : "") << by_options << " of the " << planned
    << " kerf cuts the bends asked for found no room in their parts with";
  const char* sep = " ";
  if (options.bridge != d.bridge)
    w << sep << "--bridge " << options.bridge << " mm (default " << d.bridge << ")", sep = ", ";
  if (options.margin != d.margin)
    w << sep << "--kerf-margin " << options.margin << " mm (default " << d.margin << ")",
        sep = ", ";
  if (options.min_cut_length != d.min_cut_length)
    w << sep << "--min-cut-length " << options.min_cut_length << " mm (default " << d.min_cut_length
      << ")";
  w << " but would with the defaults; where a bend needed them the parts were "
    << (at_first ? "changed (resolve.changes: flat facets, splits)"
                 : "left critical (kerf.skipped_by_options)");
  return w.str();
}

StageNotes notes(const KerfResult& k, const KerfOptions& options) {
  StageNotes n;
  Line os;
  os << k.cuts << " kerf cuts, " << k.cut_length / 1000 << " m; " << k.critical.size()
     << " critical regions (the bend needs cuts closer than " << options.min_cut_spacing
     << " mm, or no cut fits); estimated cutting time " << k.cutting.minutes << " min";
  n.lines.push_back(os.str());
  if (k.skipped_by_options > 0)
    n.warnings.push_back(skipped_cuts_warning(k.skipped_by_options, k.cuts + k.skipped, options));
  return n;
}

StageNotes notes(const ResolveResult& r, const KerfOptions& kerf, bool quads_made) {
  StageNotes n;
  std::map<std::string, int> actions;
  for (const RegionChange& c : r.changes) ++actions[c.action];
  Line os;
  os << r.critical_before << " critical regions at first, " << r.critical_after << " after "
     << r.rounds << " rebuilds (";
  bool first = true;
  for (const auto& [action, count] : actions)
    os << (first ? "" : ", ") << count << " " << action, first = false;
  os << "); parts " << r.parts_before << " -> " << r.parts_after << ", cutting " << r.minutes_before
     << " -> " << r.minutes_after << " min";
  n.lines.push_back(os.str());
  // Flat panels cut as plates are how such a model is cut, not changes to make it buildable.
  const int changed = static_cast<int>(r.changes.size()) - actions["unresolved"] - actions["plate"];
  if (r.time_limited) {
    Line w(3);
    w << "the resolve step stopped at its time limit after " << r.seconds << " s and " << r.rounds
      << " rebuilds (--resolve-time-limit); what it had not reached is listed as "
      << "unresolved (resolve.changes)";
    n.warnings.push_back(w.str());
  }
  if (actions["omit"] > 0) {
    double farthest = 0;
    for (const RegionChange& c : r.changes)
      if (c.action == "omit") farthest = std::max(farthest, c.local_distance);
    Line w(3);
    w << actions["omit"] << " parts were left out (resolve.changes, \"omit\"): faces folded back "
      << "thinner than the sheets, slivers narrower than --min-part-width, parts of which "
      << "their joints left nothing or that fell apart at their slots where the shape is "
      << "thinner than two sheets, facets flattening distorted that their joints cut back "
      << "under --min-part-area, or parts inside out (their quads folded over the parts "
      << "beside them); the surface there lies within " << farthest
      << " mm of the parts kept, whose borders with them are free edges";
    if (r.gone_parts > 0) {
      w << "; " << r.gone_parts << " had nothing left once their joints were cut";
      if (r.gone_parts_size_mm > kLargestSize)
        w << ", which no --size up to " << kLargestSize / 1000 << " m would keep";
      else if (r.gone_parts_size_mm > r.current_size_mm + 0.5)
        w << ", which --size " << whole_mm(r.gone_parts_size_mm) << " would keep";
    }
    n.warnings.push_back(w.str());
  }
  if (r.critical_after > 0 || changed > 0 || r.small_parts_after > 0) {
    Line w(4);
    bool named = false;  // a --size (or a material's) was named
    // Between the clauses: none before the first (a paper model has no critical regions, and
    // where the loop changed nothing the warning began with a bare "; ").
    const char* sep = "";
    if (changed > 0) {
      w << changed << " regions were changed to be buildable (resolve.changes)";
      sep = "; ";
    }
    const char* const stopped = "; the loop stopped at its time limit before it reached them";
    if (r.critical_after > 0 && r.narrow_after == 0) {
      w << (changed > 0 ? " and " : "") << r.critical_after << " remain critical: their cuts keep "
        << kerf.min_cut_spacing << " mm but the bend overstresses the beams there (kerf.critical"
        << (r.time_limited ? stopped : "") << ")";
      sep = "; ";
    } else if (r.critical_after > 0) {
      // Where a cut does not fit between the joints, the strip's width is what is short.
      w << (changed > 0 ? " and " : "") << r.critical_after << " remain critical (kerf.critical"
        << (r.time_limited ? stopped : "") << "): ";
      const int dense = r.critical_after - r.narrow_after;
      if (dense > 0)
        w << dense << " where the cuts keep " << kerf.min_cut_spacing
          << " mm but the bend overstresses the beams, ";
      w << r.narrow_after << " where a cut the bend needs does not fit between the part's "
        << "joints (the strip is too narrow there for the margins, the bridge and the shortest "
        << "cut)";
      if (r.narrow_size_mm > kLargestSize)
        w << ", which no --size up to " << kLargestSize / 1000 << " m would fit";
      else if (r.narrow_size_mm > r.current_size_mm + 0.5)
        w << ", which --size " << whole_mm(r.narrow_size_mm) << " would fit", named = true;
      sep = "; ";
    }
    // Parts that flatten distorted are named apart: their quads' angles are the same at every
    // size, so the size named for the others is no cure for them.
    const int sized = r.small_parts_after - r.distorted_parts_after;
    if (sized > 0) {
      w << sep << sized
        << " parts stay too small or narrow to handle (resolve.changes, \"unresolved\")";
      // Those that fell apart where their joints leave them whole have no size: the size is
      // named for the others alone.
      const int known = sized - r.unsized_parts_after;
      const std::string which =
          r.unsized_parts_after > 0 ? ", " + std::to_string(known) + " of which" : ", which";
      if (known > 0 && r.small_parts_size_mm > kLargestSize)
        w << which << " no --size up to " << kLargestSize / 1000 << " m would hold";
      else if (known > 0 && r.small_parts_size_mm > r.current_size_mm + 0.5)
        w << which << " would hold at --size " << whole_mm(r.small_parts_size_mm), named = true;
      if (r.unsized_parts_after > 0)
        w << "; for " << r.unsized_parts_after << " no size is known (fallen apart at their "
          << "slots where they are wide enough for their joints' depth)";
      sep = "; ";
    }
    if (r.distorted_parts_after > 0)
      w << sep << r.distorted_parts_after
        << " parts flatten distorted (resolve.changes, \"unresolved\": quads that do not lie flat "
           "together, or a strip that twists more than a sheet bends), which no --size cures: "
        << "the quads there would need to lie flatter"
        << (quads_made ? " (model/quads.obj edited, passed back with --quad)"
                       : " (the quad mesh edited there)");
    if (r.min_size_mm > r.current_size_mm + 0.5) {
      if (r.min_size_mm > kLargestSize)
        w << "; the tightest bends need a change at every --size up to " << kLargestSize / 1000
          << " m";
      else
        w << "; the tightest bends would need no change at --size " << whole_mm(r.min_size_mm),
            named = true;
      for (const MaterialSize& m : r.materials)
        if (m.size_mm < r.min_size_mm - 0.5) {
          if (m.size_mm <= kLargestSize)
            w << " (in --material " << m.material << " at " << whole_mm(m.size_mm) << ")",
                named = true;
          break;
        }
    }
    // The sizes are for the quads of this run; from the triangles alone a run at another size
    // makes quads of its own (the size rule), so the size holds with these passed back.
    if (named && quads_made)
      w << " (with this run's quads: add --quad model/quads.obj; from the triangles alone kerfab "
        << "makes new quads for the size asked)";
    n.warnings.push_back(w.str());
  }
  return n;
}

StageNotes notes(const LayoutResult& l, const LayoutOptions& options) {
  StageNotes n;
  Line os(3);
  os << l.placements.size() << " parts on " << l.sheets << " sheets of ";
  if (options.offcuts.empty()) {
    os << options.sheet_width << " x " << options.sheet_height << " mm";
  } else {
    for (int k = 0; k < l.sheets; ++k)
      os << (k ? ", " : "") << l.sheet_size(k).x() << " x " << l.sheet_size(k).y();
    os << " mm";
  }
  os << ", material used " << 100 * l.utilization << "%";
  if (l.sheets > 1)
    os << " (no nesting fits them on fewer than " << l.sheets_lower_bound_spaced
       << " with this spacing, " << l.sheets_lower_bound << " by area alone)";
  if (l.sheets > 1 && static_cast<int>(l.sheet_utilization.size()) == l.sheets)
    os << "; the last sheet is " << 100 * l.sheet_utilization.back() << "% used";
  n.lines.push_back(os.str());
  if (l.too_large() > 0)
    n.warnings.push_back(std::to_string(l.too_large()) +
                         " parts fit no sheet and are missing from cut/ (see layout.unplaced)");
  if (!l.empty.empty())
    n.warnings.push_back(std::to_string(l.empty.size()) +
                         " parts have nothing left once their slots and mitres are cut and are "
                         "missing from cut/ (see layout.empty and resolve.changes)");
  int unlabelled = 0;
  for (const auto& label : l.labels) unlabelled += label ? 0 : 1;
  if (unlabelled > 0)
    n.warnings.push_back(std::to_string(unlabelled) +
                         " parts have no room for their number (too small, or too narrow between "
                         "kerf cuts); the assembly guide shows each on its sheet");
  return n;
}

StageNotes notes(const SplitToFitResult& s) {
  StageNotes n;
  if (!s.saved()) return n;
  Line os(3);
  os << s.strips_split << " strips at least " << s.min_length_mm
     << " mm long split in two at their middle ruling";
  if (s.rings_recut > 0) os << ", " << s.rings_recut << " rings cut open there instead";
  os << ": " << s.sheets_after << " sheets instead of " << s.sheets_before << ", " << s.parts_after
     << " parts instead of " << s.parts_before << ", cutting " << s.minutes_after
     << " min instead of " << s.minutes_before << " (--keep-strips-whole keeps them whole)";
  n.lines.push_back(os.str());
  return n;
}

StageNotes notes(const AssemblyPlan& a) {
  StageNotes n;
  int closing = 0;
  for (const AssemblyStep& s : a.steps) closing += s.closing ? 1 : 0;
  Line os;
  os << a.steps.size() << " steps, " << a.pieces << (a.pieces == 1 ? " piece" : " pieces")
     << " grown part by part";
  if (closing > 0) os << ", the last " << closing << " filling holes";
  n.lines.push_back(os.str());
  if (a.pieces > 1)
    n.warnings.push_back("the parts make " + std::to_string(a.pieces) +
                         " separate pieces: no shared border joins them (assembly.pieces)");
  return n;
}

StageNotes notes(const SurfaceDistance& q, double diagonal) {
  StageNotes n;
  Line os;
  os << "strips vs target: Hausdorff " << q.hausdorff << " mm (" << 100 * q.hausdorff / diagonal
     << "% of diagonal)";
  if (q.hausdorff > 0) {  // where: the point of the surface farthest from the other
    const Vec3& at = q.hausdorff_at();
    os << " at (" << at.x() << ", " << at.y() << ", " << at.z() << ") mm on the "
       << (q.hausdorff_on_a ? "strips (model/strips.ply)" : "target (model/target.obj)");
  }
  os << ", mean " << q.mean << " mm (" << 100 * q.mean / diagonal << "%), " << q.samples
     << " distance queries (true Hausdorff at most " << q.hausdorff_upper_bound()
     << " mm; mean from samples " << q.spacing << " mm apart, off by about "
     << q.mean_error_estimate << " mm)";
  n.lines.push_back(os.str());
  return n;
}

StageNotes notes(const ShellClearance& c, double size_mm, bool quads_made) {
  StageNotes n;
  if (!(c.thickness > 0)) return n;
  Line os;
  os << "shell clearance: " << c.samples << " samples " << c.spacing << " mm apart; ";
  if (c.contacts.empty()) {
    os << "no two stretches of the surface closer than the " << c.thickness << " mm sheets";
    n.lines.push_back(os.str());
    return n;
  }
  os << c.contacts.size() << " pairs of parts closer than the " << c.thickness
     << " mm sheets, the narrowest " << c.min_gap() << " mm apart";
  n.lines.push_back(os.str());
  std::vector<const ClearanceContact*> thin;
  std::map<int, std::vector<const ClearanceContact*>> reversed;  // part inside out -> contacts
  double thin_area = 0;
  for (const ClearanceContact& k : c.contacts)
    if (k.inside_out >= 0)
      reversed[k.inside_out].push_back(&k);
    else
      thin.push_back(&k), thin_area += k.area;
  auto where = [](Line& w, const ClearanceContact& k) {
    w << k.gap << " mm apart at (" << k.at.x() << ", " << k.at.y() << ", " << k.at.z() << ") mm";
  };
  if (!thin.empty()) {
    Line w;
    w << "the shape is thinner than its " << c.thickness << " mm sheets in " << thin.size()
      << (thin.size() == 1 ? " place" : " places") << " (" << whole_mm(thin_area)
      << " mm^2 of surface): two stretches of it, apart along the surface, come closer than the "
         "sheets are thick, so two parts' sheets would stand in the same place "
         "(quality.clearance); ";
    for (std::size_t i = 0; i < thin.size() && i < kBordersNamed; ++i) {
      const ClearanceContact& k = *thin[i];
      w << (i ? ", " : "");
      if (k.part_a == k.part_b)
        w << "part " << k.part_a << " against itself ";
      else
        w << "parts " << k.part_a << " and " << k.part_b << " ";
      where(w, k);
    }
    if (thin.size() > kBordersNamed) w << ", ...";
    const double factor = c.size_factor();
    if (factor <= 0)
      w << "; the surface meets itself there, which no --size cures (the target intersects "
           "itself)";
    else if (factor * size_mm > kLargestSize)
      w << "; no --size up to " << kLargestSize / 1000 << " m clears them";
    else
      w << "; at --size " << whole_mm(factor * size_mm) << " every gap reaches the thickness, "
        << "and at this size sheets of at most " << c.min_thin_gap()
        << " mm (--thickness) would clear";
    n.warnings.push_back(w.str());
  }
  if (!reversed.empty()) {
    Line w;
    const bool one = reversed.size() == 1;
    w << reversed.size()
      << (one ? " part lies inside out over the parts beside it, its"
              : " parts lie inside out over the parts beside them, their")
      << " faces turned against the target's (quality.clearance, \"inside_out\"): ";
    std::size_t named = 0;
    for (const auto& [part, list] : reversed) {
      if (named++ == kBordersNamed) {
        w << ", ...";
        break;
      }
      w << (named > 1 ? "; " : "") << "part " << part << " over part";
      w << (list.size() > 1 ? "s " : " ");
      for (std::size_t i = 0; i < list.size(); ++i)
        w << (i ? ", " : "") << (list[i]->part_a == part ? list[i]->part_b : list[i]->part_a);
      w << " ";
      where(w, *list.front());
    }
    w << "; the quads fold over there, which no --size cures: the quads there would need to lie "
         "flat"
      << (quads_made ? " (model/quads.obj edited, passed back with --quad, or another --quads)"
                     : " (the quad mesh edited there)");
    n.warnings.push_back(w.str());
  }
  return n;
}

}  // namespace kerfab
