// lista-train: reproduces models/describe-learned.bin from scratch.
//   lista-train --views <lista-sim views folder> --out models/describe-learned.bin
//   lista-train --synthetic 400 ...   (built-in synthetic shapes, for quick checks)
#include "train.hpp"
#include <lista_objfeat/views.hpp>

#include <lista/error.hpp>

#include <CLI/CLI.hpp>
#include <lista_cli/parse.hpp>
#include <cstdio>

int main(int argc, char** argv) {
  using namespace lista::train;
  using namespace lista::objfeat;
  CLI::App app{"Train the describe.learned object descriptor (metric learning on shape identity)"};
  std::vector<std::string> views_dirs;
  int synthetic = 0, per_instance = 6;
  double holdout = 0.2;
  TrainConfig cfg;
  app.add_option("--views", views_dirs, "lista-sim views folder(s) (docs/datasets.md); several are one set, by shape");
  app.add_option("--synthetic", synthetic, "use N built-in synthetic shapes instead of --views")
      ->check(CLI::Range(1, 100000));
  app.add_option("--views-per-instance", per_instance, "synthetic views per instance")->check(CLI::Range(2, 100));
  app.add_option("--holdout", holdout,
                 "fraction of shapes held out for evaluation (--synthetic; a views folder keeps its own split)")
      ->check(CLI::Range(0.0, 0.9));
  app.add_option("--steps", cfg.steps, "optimisation steps")->check(CLI::Range(1, 1000000));
  app.add_option("--batch-instances", cfg.instances_per_batch, "instances per batch (P)")->check(CLI::Range(2, 1024));
  app.add_option("--batch-views", cfg.views_per_instance, "views per instance per batch (K)")->check(CLI::Range(2, 64));
  app.add_option("--lr", cfg.lr, "Adam learning rate")->check(CLI::Range(1e-6, 1.0));
  app.add_option("--loss", cfg.loss, "triplet (batch-hard, default) or proxy (normalised softmax over shape proxies)")
      ->check(CLI::IsMember({"proxy", "triplet"}));
  app.add_option("--scale", cfg.scale, "proxy loss scale (inverse temperature)")->check(CLI::Range(1.0, 100.0));
  app.add_option("--margin", cfg.margin, "triplet margin")->check(CLI::Range(0.0, 2.0));
  app.add_option("--dim", cfg.dim, "descriptor dimension")->check(CLI::Range(2, 1024));
  app.add_option("--channels", cfg.channels, "canonical channels per point: 6 (with height above the lowest point) or 5")
      ->check(CLI::Range(kFirstModelChannels, kCanonicalChannels));
  app.add_option("--grid", cfg.grid, "voxel cells along the object's largest extent")->check(CLI::Range(4, 256));
  app.add_option("--points", cfg.points, "resampled points per object")->check(CLI::Range(16, 4096));
  app.add_option("--frame", cfg.frame, "yaw frame: rectangle (minimum-perimeter footprint rectangle) or principal (axis)")
      ->check(CLI::IsMember({"rectangle", "principal"}));
  bool no_globals = false;
  app.add_flag("--no-globals", no_globals, "do not give the head the object's extents (the first model's layout)");
  app.add_option("--globals", cfg.globals,
                 "shape globals the head reads: 10 (all, canonical.hpp), 9 (all but the lowest point's height above "
                 "the floor), 4 (extents and centroid height) or 0")
      ->check(CLI::IsMember({0, kExtentGlobals, kNoFloorGlobals, kShapeGlobals}));
  bool no_floor = false;
  auto* no_floor_flag = app.add_flag("--no-floor", no_floor,
               "measure heights from the lowest point, never from the floor (the models before 2026-11-26)");
  app.add_option("--floor-dropout", cfg.floor_dropout,
                 "share of training samples given no floor (so an unknown floor still describes well)")
      ->check(CLI::Range(0.0, 1.0))->excludes(no_floor_flag);
  std::vector<int> widths;
  app.add_option("--widths", widths, "per-point MLP widths and head width: w1,w2,w3,head")
      ->delimiter(',')->expected(4)->check(CLI::Range(4, 2048));
  app.add_option("--ema", cfg.ema, "decay of the weights' moving average that is evaluated and saved (0: off)")
      ->check(CLI::Range(0.0, 0.99999));
  app.add_flag("--balance-sources", cfg.balance_sources,
               "give every shape source (procedural, furniture, ...) an equal share of each batch");
  auto* lookalike_group = app.add_option("--lookalike-group", cfg.lookalike_group,
                 "fill batches with groups of this many shapes of nearly one size (1: uniform draw)")
      ->check(CLI::Range(1, 64))->excludes("--balance-sources");
  app.add_option("--lookalike-share", cfg.lookalike_share, "share of each batch's shapes drawn in look-alike groups")
      ->check(CLI::Range(0.0, 1.0))->needs(lookalike_group);
  app.add_option("--lookalike-from", cfg.lookalike_from,
                 "first step with look-alike groups (uniform batches before; from step 1 they collapse training)")
      ->check(CLI::Range(0, 1000000))->needs(lookalike_group);
  app.add_option("--seed", cfg.seed, "seed (same seed, same weights)");
  app.add_option("--threads", cfg.threads, "torch threads")->check(CLI::Range(1, 256));
  app.add_option("--eval-every", cfg.eval_every, "steps between held-out evaluations")->check(CLI::Range(1, 1000000));
  bool overwrite = false;
  app.add_option("--out", cfg.out, "weights file to write (a .sha256 sidecar is written next to it)")->required();
  app.add_flag("--overwrite", overwrite, "replace --out if it exists (e.g. the shipped models/describe-learned.bin)");
  if (auto code = lista::cli::parse_command_line(app, argc, argv, "lista-train")) return *code;
  if (no_globals) cfg.globals = 0;
  cfg.floor = !no_floor;
  if (!widths.empty()) { cfg.w1 = widths[0]; cfg.w2 = widths[1]; cfg.w3 = widths[2]; cfg.head = widths[3]; }

  try {
    prepare_output(cfg.out, overwrite);
    ViewSet all;
    if (!views_dirs.empty()) all = read_views(views_dirs, ViewChannels::xyz_only);  // training reads xyz alone
    else if (synthetic > 0) all = synthetic_views(synthetic, per_instance, cfg.seed);
    else throw lista::Error("give --views <folder> (lista-sim views) or --synthetic <shapes>");
    ViewSet train, test;
    split_by_shape(all, holdout, cfg.seed, train, test);
    std::fprintf(stderr, "%zu views: %zu for training, %zu held out (by shape)\n", all.views.size(),
                 train.views.size(), test.views.size());
    if (test.views.empty())
      std::fprintf(stderr, "lista-train: warning: no held-out views (index.json split 'val' or 'test'); the "
                           "held-out scores printed are not measurements\n");
    TrainResult r = train_descriptor(train, test, cfg);
    std::printf("wrote %s in %.0f s; held-out top1 %.3f mAP %.3f\n", cfg.out.c_str(), r.seconds, r.test_top1,
                r.test_map);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lista-train: %s\n", e.what());
    return 1;
  }
  return 0;
}
