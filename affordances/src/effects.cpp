// Effect categories (k-means on the standardised changes, k by BIC), the tree that predicts them
// (OpenCV's DTrees) read back as rules, and the learned domain written from both.
#include "macsim/affordances/effects.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <opencv2/core.hpp>
#include <opencv2/ml.hpp>
#include <set>
#include <sstream>
#include <stdexcept>

#include "macsim/affordances/model.h"

namespace macsim::affordances {
namespace {

using pddl::Atom;

/// k-means with OpenCV's generator seeded for this k (the global generator restored after).
/// The least distance between two of the centres.
double kmeans(const cv::Mat& data, int k, cv::Mat& labels) {
  cv::RNG& rng = cv::theRNG();
  const cv::RNG saved = rng;
  rng.state = 0x5eed0000ULL + static_cast<std::uint64_t>(k);
  cv::Mat centres;
  cv::kmeans(data, k, labels,
             cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 200, 1e-7), 5,
             cv::KMEANS_PP_CENTERS, centres);
  rng = saved;
  double nearest = INFINITY;
  for (int a = 0; a < k; ++a)
    for (int b = a + 1; b < k; ++b)
      nearest = std::min(nearest, cv::norm(centres.row(a), centres.row(b), cv::NORM_L2));
  return nearest;
}

/// The mean silhouette of a partition (a trial alone in its group counts 0).
double silhouette(const cv::Mat& data, const std::vector<int>& labels, int k) {
  const int n = data.rows;
  std::vector<int> size(k, 0);
  for (const int l : labels) ++size[l];
  double total = 0;
  std::vector<double> sum(k);
  for (int i = 0; i < n; ++i) {
    std::fill(sum.begin(), sum.end(), 0.0);
    for (int j = 0; j < n; ++j)
      if (j != i) sum[labels[j]] += cv::norm(data.row(i), data.row(j), cv::NORM_L2);
    const int own = labels[i];
    if (size[own] <= 1) continue;
    const double a = sum[own] / (size[own] - 1);
    double b = INFINITY;
    for (int c = 0; c < k; ++c)
      if (c != own && size[c] > 0) b = std::min(b, sum[c] / size[c]);
    if (std::isfinite(b) && std::max(a, b) > 0) total += (b - a) / std::max(a, b);
  }
  return total / std::max(n, 1);
}

/// Adjusted Rand index of two partitions (Hubert and Arabie).
double adjusted_rand(const std::vector<int>& a, const std::vector<std::string>& b) {
  const auto pairs = [](double x) { return x * (x - 1) / 2; };
  std::map<std::pair<int, std::string>, int> both;
  std::map<int, int> by_a;
  std::map<std::string, int> by_b;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ++both[{a[i], b[i]}];
    ++by_a[a[i]];
    ++by_b[b[i]];
  }
  double index = 0, sum_a = 0, sum_b = 0;
  for (const auto& [key, count] : both) index += pairs(count);
  for (const auto& [key, count] : by_a) sum_a += pairs(count);
  for (const auto& [key, count] : by_b) sum_b += pairs(count);
  const double expected = sum_a * sum_b / std::max(pairs(static_cast<double>(a.size())), 1.0);
  const double maximum = 0.5 * (sum_a + sum_b);
  if (maximum - expected == 0) return 1;  // both one group (or each trial alone)
  return (index - expected) / (maximum - expected);
}

/// The atoms added and removed from before to after.
std::pair<std::set<Atom>, std::set<Atom>> atom_changes(const EffectTrial& t) {
  const std::set<Atom> before(t.atoms_before.begin(), t.atoms_before.end());
  const std::set<Atom> after(t.atoms_after.begin(), t.atoms_after.end());
  std::set<Atom> added, removed;
  std::set_difference(after.begin(), after.end(), before.begin(), before.end(),
                      std::inserter(added, added.end()));
  std::set_difference(before.begin(), before.end(), after.begin(), after.end(),
                      std::inserter(removed, removed.end()));
  return {added, removed};
}

/// The number with 4 significant digits, '.' as 'p' and '-' as 'm' (a PDDL name's characters).
std::string name_number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4g", v);
  std::string s;
  for (const char c : std::string(buffer)) s += c == '.' ? 'p' : c == '-' ? 'm' : c == '+' ? 'P' : c;
  return s;
}

std::string format(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4g", v);
  return buffer;
}

/// The tree's inputs of one trial: its features, then 1 or 0 per input atom.
std::vector<float> inputs_of(const std::vector<double>& before, const std::vector<Atom>& atoms_before,
                             const std::vector<Atom>& input_atoms) {
  std::vector<float> row(before.begin(), before.end());
  const std::set<Atom> held(atoms_before.begin(), atoms_before.end());
  for (const auto& a : input_atoms) row.push_back(held.count(a) ? 1.f : 0.f);
  return row;
}

bool meets(const Rule& rule, const std::vector<float>& row) {
  return std::all_of(rule.conditions.begin(), rule.conditions.end(), [&](const Condition& c) {
    const double v = row[c.feature];
    return c.at_most ? v <= c.value : v > c.value;
  });
}

/// A node of a fitted tree with the training trials that reached it, per category.
struct TreeNode {
  int feature = -1;  // -1: a leaf
  double value = 0;
  bool left_at_most = true;  // the left child takes feature <= value
  int left = -1, right = -1;
  std::map<int, int> trials;
};

/// Pearson's chi-square of the categories in two children, and whether it is significant at
/// 1 % (df = categories - 1).
bool significant_split(const std::map<int, int>& left, const std::map<int, int>& right) {
  std::map<int, int> both = left;
  for (const auto& [c, n] : right) both[c] += n;
  int total_left = 0, total_right = 0;
  for (const auto& [c, n] : left) total_left += n;
  for (const auto& [c, n] : right) total_right += n;
  const double total = total_left + total_right;
  if (total_left == 0 || total_right == 0) return false;
  double chi2 = 0;
  int categories = 0;
  for (const auto& [c, n] : both) {
    if (n == 0) continue;
    ++categories;
    for (const auto& [side, side_total] : {std::pair{&left, total_left}, std::pair{&right, total_right}}) {
      const double expected = static_cast<double>(n) * side_total / total;
      const auto it = side->find(c);
      const double observed = it == side->end() ? 0 : it->second;
      chi2 += (observed - expected) * (observed - expected) / expected;
    }
  }
  // The 99th percentiles of chi-square with 1..7 degrees of freedom.
  static constexpr double kCritical[] = {6.635, 9.210, 11.345, 13.277, 15.086, 16.812, 18.475};
  const int df = std::clamp(categories - 1, 1, 7);
  return categories > 1 && chi2 > kCritical[df - 1];
}

std::pair<int, int> majority(const std::map<int, int>& trials) {
  int category = 0, most = -1, total = 0;
  for (const auto& [c, count] : trials) {
    total += count;
    if (count > most) {
      most = count;
      category = c;
    }
  }
  return {category, total - std::max(most, 0)};
}

/// OpenCV's DTrees grown without pruning (its cross-validated pruning is not implemented), pruned
/// here from the leaves up: a split of two leaves whose categories do not differ significantly
/// (chi-square, 1 %) becomes one leaf.
class PrunedTree {
 public:
  PrunedTree(const cv::ml::DTrees& tree, const cv::Mat& x, const std::vector<int>& y) {
    const auto& nodes = tree.getNodes();
    const auto& splits = tree.getSplits();
    const auto copy = [&](auto&& self, int at) -> int {
      const int index = static_cast<int>(nodes_.size());
      nodes_.emplace_back();
      const auto& n = nodes[at];
      if (n.split >= 0) {
        const auto& split = splits[n.split];
        // OpenCV sends a sample left when its value is at most c (the other way when inversed).
        nodes_[index].feature = split.varIdx;
        nodes_[index].value = split.c;
        nodes_[index].left_at_most = !split.inversed;
        const int left = self(self, n.left);
        const int right = self(self, n.right);
        nodes_[index].left = left;
        nodes_[index].right = right;
      }
      return index;
    };
    copy(copy, tree.getRoots().at(0));
    for (int r = 0; r < x.rows; ++r)
      for (int at = 0;;) {
        ++nodes_[at].trials[y[r]];
        const TreeNode& n = nodes_[at];
        if (n.feature < 0) break;
        const bool at_most = x.at<float>(r, n.feature) <= n.value;
        at = at_most == n.left_at_most ? n.left : n.right;
      }
    prune(0);
  }

  /// The leaves as rules (conditions from the root down; the tightest per input and direction).
  std::vector<Rule> rules() const {
    std::vector<Rule> out;
    std::vector<Condition> path;
    const auto descend = [&](auto&& self, int at) -> void {
      const TreeNode& n = nodes_[at];
      if (n.feature < 0) {
        Rule r;
        r.category = majority(n.trials).first;
        r.trials_per_category = n.trials;
        for (const auto& c : path) {
          const auto same = std::find_if(r.conditions.begin(), r.conditions.end(), [&](const Condition& o) {
            return o.feature == c.feature && o.at_most == c.at_most;
          });
          if (same == r.conditions.end()) r.conditions.push_back(c);
          else same->value = c.at_most ? std::min(same->value, c.value) : std::max(same->value, c.value);
        }
        out.push_back(std::move(r));
        return;
      }
      path.push_back({n.feature, n.value, n.left_at_most});
      self(self, n.left);
      path.back().at_most = !n.left_at_most;
      self(self, n.right);
      path.pop_back();
    };
    descend(descend, 0);
    return out;
  }

 private:
  /// Prunes below `at`; true when `at` is a leaf afterwards.
  bool prune(int at) {
    if (nodes_[at].feature < 0) return true;
    const int left = nodes_[at].left, right = nodes_[at].right;
    const bool leaves = prune(left) & prune(right);
    if (leaves && !significant_split(nodes_[left].trials, nodes_[right].trials)) {
      nodes_[at].feature = -1;
      return true;
    }
    return false;
  }

  std::vector<TreeNode> nodes_;
};

/// A tree fitted on the rows (OpenCV's DTrees, depth 4 at most), pruned, as rules.
std::vector<Rule> fit_rules(const cv::Mat& x, const std::vector<int>& y) {
  auto tree = cv::ml::DTrees::create();
  tree->setMaxDepth(4);
  tree->setMinSampleCount(std::max(2, x.rows / 40));
  tree->setCVFolds(0);
  tree->setUseSurrogates(false);
  tree->setUse1SERule(false);
  tree->setTruncatePrunedTree(false);
  tree->setRegressionAccuracy(0);
  tree->setMaxCategories(16);
  cv::Mat labels(static_cast<int>(y.size()), 1, CV_32S);
  for (std::size_t i = 0; i < y.size(); ++i) labels.at<int>(static_cast<int>(i)) = y[i];
  cv::Mat types(x.cols + 1, 1, CV_8U, cv::Scalar(cv::ml::VAR_ORDERED));
  types.at<uchar>(x.cols) = cv::ml::VAR_CATEGORICAL;
  tree->train(cv::ml::TrainData::create(x, cv::ml::ROW_SAMPLE, labels, cv::noArray(), cv::noArray(),
                                        cv::noArray(), types));
  return PrunedTree(*tree, x, y).rules();
}

void check(const BehaviourTrials& t) {
  for (const auto& trial : t.trials) {
    if (trial.before.size() != t.features.size() || trial.change.size() != t.changes.size())
      throw std::invalid_argument(t.behaviour + " trial " + std::to_string(trial.seed) +
                                  ": its features or changes do not match the columns");
    for (const double v : trial.before)
      if (!std::isfinite(v)) throw std::invalid_argument(t.behaviour + " trial " + std::to_string(trial.seed) + ": a feature is not finite");
    for (const double v : trial.change)
      if (!std::isfinite(v)) throw std::invalid_argument(t.behaviour + " trial " + std::to_string(trial.seed) + ": a change is not finite");
  }
}

/// What the trials of category `category` that meet `rule` changed: the atoms more than half of
/// them added or removed (the category's effect in that rule's context).
pddl::Outcome effect_in_rule(const BehaviourTrials& t, const LearnedBehaviour& l, const Rule& rule,
                             int category) {
  std::map<Atom, int> added, removed;
  int members = 0;
  for (std::size_t i = 0; i < t.trials.size(); ++i) {
    if (l.categories.of_trial[i] != category ||
        !meets(rule, inputs_of(t.trials[i].before, t.trials[i].atoms_before, l.input_atoms)))
      continue;
    ++members;
    const auto [add, remove] = atom_changes(t.trials[i]);
    for (const auto& a : add) ++added[a];
    for (const auto& a : remove) ++removed[a];
  }
  pddl::Outcome o;
  for (const auto& [a, count] : added)
    if (2 * count > members) o.add.push_back(a);
  for (const auto& [a, count] : removed)
    if (2 * count > members) o.remove.push_back(a);
  return o;
}

}  // namespace

std::string threshold_predicate(const std::string& feature, double value) {
  std::string name;
  for (const char c : feature) name += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_')
                                           ? static_cast<char>(std::tolower(static_cast<unsigned char>(c)))
                                           : '_';
  return name + "-le-" + name_number(value);
}

void keep_typed_atoms(const pddl::Domain& vocabulary, BehaviourTrials& trials) {
  std::map<std::string, std::string> type_of;
  for (const auto& p : trials.parameters) type_of[p.name] = p.type;
  const auto typed = [&](const Atom& a) {
    const auto d = std::find_if(vocabulary.predicates.begin(), vocabulary.predicates.end(),
                                [&](const pddl::PredicateDeclaration& p) { return p.name == a.predicate; });
    if (d == vocabulary.predicates.end() || d->parameters.size() != a.arguments.size()) return false;
    for (std::size_t i = 0; i < a.arguments.size(); ++i) {
      const auto t = type_of.find(a.arguments[i]);
      if (t == type_of.end() || !pddl::is_a(vocabulary, t->second, d->parameters[i].type)) return false;
    }
    return true;
  };
  for (auto& t : trials.trials) {
    std::erase_if(t.atoms_before, [&](const Atom& a) { return !typed(a); });
    std::erase_if(t.atoms_after, [&](const Atom& a) { return !typed(a); });
  }
}

EffectCategories categorise(const BehaviourTrials& trials, int max_k) {
  check(trials);
  EffectCategories out;
  const int n = static_cast<int>(trials.trials.size());
  const int d = static_cast<int>(trials.changes.size());
  // Each column in units of its resolution.
  cv::Mat data(n, std::max(d, 1), CV_32F, cv::Scalar(0));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < d; ++j)
      data.at<float>(i, j) = static_cast<float>(trials.trials[i].change[j] /
                                                std::max(trials.changes[j].resolution, 1e-12));
  std::vector<int> best(n, 0);
  double best_silhouette = kClearSilhouette;
  int best_k = 1;
  for (int k = 2; k <= std::min(max_k, n - 1); ++k) {
    cv::Mat l;
    // Groups whose mean changes lie closer than the sensors' resolution are one category.
    if (kmeans(data, k, l) < 1.0) continue;
    std::vector<int> labels(n);
    for (int i = 0; i < n; ++i) labels[i] = l.at<int>(i);
    const double s = silhouette(data, labels, k);
    out.silhouette.push_back(s);
    if (s > best_silhouette + 1e-9) {
      best_silhouette = s;
      best_k = k;
      best = labels;
    }
  }
  // Categories numbered by size, the commonest 0 (ties: the smaller first change first).
  std::vector<int> size(best_k, 0);
  for (const int l : best) ++size[l];
  std::vector<std::vector<double>> centre(best_k, std::vector<double>(d, 0));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < d; ++j) centre[best[i]][j] += trials.trials[i].change[j] / size[best[i]];
  std::vector<int> order(best_k);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    if (size[a] != size[b]) return size[a] > size[b];
    return centre[a] < centre[b];
  });
  std::vector<int> rank(best_k);
  for (int r = 0; r < best_k; ++r) rank[order[r]] = r;
  out.count = best_k;
  out.of_trial.resize(n);
  for (int i = 0; i < n; ++i) out.of_trial[i] = rank[best[i]];
  for (int r = 0; r < best_k; ++r) out.centres.push_back(centre[order[r]]);
  // Each category's effect on the atoms: what more than half of its trials added or removed.
  out.effects.assign(best_k, pddl::Outcome{});
  std::vector<std::map<Atom, int>> added(best_k), removed(best_k);
  std::vector<int> members(best_k, 0);
  std::vector<std::string> labels;
  for (int i = 0; i < n; ++i) {
    const int c = out.of_trial[i];
    ++members[c];
    const auto [add, remove] = atom_changes(trials.trials[i]);
    for (const auto& a : add) ++added[c][a];
    for (const auto& a : remove) ++removed[c][a];
    ++out.with_label[{c, trials.trials[i].label}];
    labels.push_back(trials.trials[i].label);
  }
  for (int c = 0; c < best_k; ++c) {
    for (const auto& [a, count] : added[c])
      if (2 * count > members[c]) out.effects[c].add.push_back(a);
    for (const auto& [a, count] : removed[c])
      if (2 * count > members[c]) out.effects[c].remove.push_back(a);
  }
  out.adjusted_rand = adjusted_rand(out.of_trial, labels);
  return out;
}

LearnedBehaviour learn_behaviour(const BehaviourTrials& trials, int max_k) {
  LearnedBehaviour out;
  out.behaviour = trials.behaviour;
  out.categories = categorise(trials, max_k);
  const std::size_t n = trials.trials.size();
  // Atoms before: those that held in every trial are the behaviour's context; those that held in
  // some are the tree's inputs.
  std::map<Atom, std::size_t> held;
  for (const auto& t : trials.trials)
    for (const auto& a : std::set<Atom>(t.atoms_before.begin(), t.atoms_before.end())) ++held[a];
  for (const auto& [a, count] : held) {
    if (count == n) out.always_before.push_back(a);
    else out.input_atoms.push_back(a);
  }
  std::set<Atom> made;
  for (const auto& t : trials.trials) made.insert(t.atoms_after.begin(), t.atoms_after.end());
  for (const auto& a : made)
    if (!held.count(a)) out.never_before.push_back(a);
  for (const auto& f : trials.features) out.inputs.push_back(f.name);
  for (const auto& a : out.input_atoms) out.inputs.push_back(pddl::text(a));
  const int columns = static_cast<int>(out.inputs.size());
  const auto matrix = [&](const std::vector<std::size_t>& rows) {
    cv::Mat x(static_cast<int>(rows.size()), std::max(columns, 1), CV_32F, cv::Scalar(0));
    for (std::size_t r = 0; r < rows.size(); ++r) {
      const auto row = inputs_of(trials.trials[rows[r]].before, trials.trials[rows[r]].atoms_before,
                                 out.input_atoms);
      for (int j = 0; j < columns; ++j) x.at<float>(static_cast<int>(r), j) = row[j];
    }
    return x;
  };
  std::vector<std::size_t> all(n), train, test;
  std::iota(all.begin(), all.end(), 0);
  for (const auto i : all) (held_out(trials.trials[i].seed) ? test : train).push_back(i);
  const auto categories_of = [&](const std::vector<std::size_t>& rows) {
    std::vector<int> y;
    for (const auto i : rows) y.push_back(out.categories.of_trial[i]);
    return y;
  };
  if (out.categories.count <= 1 || columns == 0) {
    // One category (or nothing to decide by): one rule without conditions, never wrong.
    Rule r;
    for (std::size_t i = 0; i < n; ++i) ++r.trials_per_category[out.categories.of_trial[i]];
    out.rules = {r};
    out.held_out_trials = static_cast<int>(test.size());
    int right = 0;
    for (const auto i : test) right += out.categories.of_trial[i] == 0;
    out.held_out_accuracy = test.empty() ? 0 : static_cast<double>(right) / test.size();
    return out;
  }
  if (!train.empty() && !test.empty()) {
    const std::vector<Rule> rules = fit_rules(matrix(train), categories_of(train));
    int right = 0;
    for (const auto i : test) {
      const auto row = inputs_of(trials.trials[i].before, trials.trials[i].atoms_before, out.input_atoms);
      for (const auto& r : rules)
        if (meets(r, row)) {
          right += r.category == out.categories.of_trial[i];
          break;
        }
    }
    out.held_out_trials = static_cast<int>(test.size());
    out.held_out_accuracy = static_cast<double>(right) / test.size();
  }
  out.rules = fit_rules(matrix(all), categories_of(all));
  return out;
}

const Rule& rule_for(const LearnedBehaviour& learned, const std::vector<double>& before,
                     const std::vector<Atom>& atoms_before) {
  const auto row = inputs_of(before, atoms_before, learned.input_atoms);
  for (const auto& r : learned.rules)
    if (meets(r, row)) return r;
  throw std::logic_error(learned.behaviour + ": no rule meets these inputs");
}

LearnedDomain learned_domain(const pddl::Domain& vocabulary,
                             const std::vector<BehaviourTrials>& trials,
                             const std::vector<LearnedBehaviour>& learned) {
  if (trials.size() != learned.size())
    throw std::invalid_argument("learned_domain: a learned behaviour for each behaviour's trials");
  LearnedDomain out;
  out.domain.name = vocabulary.name;
  out.domain.types = vocabulary.types;
  out.domain.predicates = vocabulary.predicates;
  for (std::size_t b = 0; b < trials.size(); ++b) {
    const BehaviourTrials& t = trials[b];
    const LearnedBehaviour& l = learned[b];
    const auto type_of = [&](const std::string& parameter) {
      for (const auto& p : t.parameters)
        if (p.name == parameter) return p.type;
      throw std::invalid_argument(t.behaviour + ": feature of unknown parameter " + parameter);
    };
    int number = 0;
    for (const Rule& rule : l.rules) {
      pddl::Operator op;
      op.name = t.behaviour + "-" + std::to_string(++number);
      op.parameters = t.parameters;
      op.requires_true = l.always_before;
      op.requires_false = l.never_before;
      std::string why;
      for (const Condition& c : rule.conditions) {
        const std::size_t f = static_cast<std::size_t>(c.feature);
        if (f < t.features.size()) {
          const Feature& feature = t.features[f];
          Threshold threshold{threshold_predicate(feature.name, c.value), feature.name,
                              type_of(feature.parameter), c.value};
          const auto known = std::find_if(out.thresholds.begin(), out.thresholds.end(),
                                          [&](const Threshold& o) { return o.predicate == threshold.predicate; });
          if (known == out.thresholds.end()) {
            out.thresholds.push_back(threshold);
            out.domain.predicates.push_back({threshold.predicate, {{"?x", threshold.type}}});
          }
          const Atom atom{threshold.predicate, {feature.parameter}};
          (c.at_most ? op.requires_true : op.requires_false).push_back(atom);
          why += std::string(why.empty() ? "" : ", ") + feature.name + " of " + feature.parameter +
                 (c.at_most ? " <= " : " > ") + format(c.value);
        } else {
          const Atom& atom = l.input_atoms.at(f - t.features.size());
          // A 0/1 input: at most 0.5 is "does not hold".
          (c.at_most ? op.requires_false : op.requires_true).push_back(atom);
          why += std::string(why.empty() ? "" : ", ") + (c.at_most ? "not " : "") + l.inputs[f];
        }
      }
      int total = 0;
      for (const auto& [c, count] : rule.trials_per_category) total += count;
      std::string seen;
      for (const auto& [c, count] : rule.trials_per_category) {
        if (count == 0) continue;
        pddl::Outcome o = effect_in_rule(t, l, rule, c);
        o.probability = static_cast<double>(count) / total;
        seen += " e" + std::to_string(c + 1) + ":" + std::to_string(count);
        const auto same = std::find_if(op.outcomes.begin(), op.outcomes.end(), [&](const pddl::Outcome& x) {
          return x.add == o.add && x.remove == o.remove;
        });
        if (same != op.outcomes.end()) same->probability += o.probability;
        else op.outcomes.push_back(std::move(o));
      }
      std::stable_sort(op.outcomes.begin(), op.outcomes.end(),
                       [](const pddl::Outcome& x, const pddl::Outcome& y) { return x.probability > y.probability; });
      op.note = t.behaviour + ", rule " + std::to_string(number) + " of " + std::to_string(l.rules.size()) +
                ": " + (why.empty() ? "always" : why) + "\n" + std::to_string(total) +
                " trials, per effect category:" + seen;
      out.domain.operators.push_back(std::move(op));
    }
  }
  return out;
}

namespace {

std::string exact(double v) {
  char buffer[32];
  const auto [end, error] = std::to_chars(buffer, buffer + sizeof buffer, v);
  return error == std::errc() ? std::string(buffer, end) : "nan";
}

std::vector<std::string> split(const std::string& s, char by) {
  std::vector<std::string> out;
  std::string part;
  std::istringstream in(s);
  while (std::getline(in, part, by)) out.push_back(part);
  if (!s.empty() && s.back() == by) out.emplace_back();
  return out;
}

}  // namespace

std::string write_effect_trials(const std::vector<BehaviourTrials>& all) {
  std::ostringstream out;
  out << "behaviour,parameters,seed,label,features,changes,atoms_before,atoms_after\n";
  for (const auto& b : all) {
    std::string parameters;
    for (const auto& p : b.parameters) parameters += (parameters.empty() ? "" : ";") + p.name + " - " + p.type;
    for (const auto& t : b.trials) {
      std::string features, changes;
      for (std::size_t i = 0; i < b.features.size(); ++i)
        features += (i ? ";" : "") + b.features[i].name + ":" + b.features[i].parameter + "=" + exact(t.before[i]);
      for (std::size_t i = 0; i < b.changes.size(); ++i)
        changes += (i ? ";" : "") + b.changes[i].name + "@" + exact(b.changes[i].resolution) + "=" + exact(t.change[i]);
      out << b.behaviour << "," << parameters << "," << t.seed << "," << t.label << "," << features << ","
          << changes << "," << pddl::text(t.atoms_before) << "," << pddl::text(t.atoms_after) << "\n";
    }
  }
  return out.str();
}

std::vector<BehaviourTrials> read_effect_trials(const std::string& text, const std::string& file) {
  std::vector<BehaviourTrials> out;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  const auto fail = [&](const std::string& what) -> void {
    throw pddl::PddlError(file + ":" + std::to_string(number) + ": " + what);
  };
  const auto number_of = [&](const std::string& s, const std::string& field) {
    double v = 0;
    const auto [end, error] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (error != std::errc() || end != s.data() + s.size() || !std::isfinite(v))
      fail(field + ": '" + s + "' is no finite number");
    return v;
  };
  const auto atoms_of = [&](const std::string& s, const std::string& field) {
    std::vector<Atom> atoms;
    if (s.empty()) return atoms;
    // "(p a b) (q)": one atom per parenthesised group.
    std::size_t at = 0;
    while (at < s.size()) {
      if (s[at] == ' ') {
        ++at;
        continue;
      }
      const auto close = s.find(')', at);
      if (s[at] != '(' || close == std::string::npos) fail(field + ": '" + s + "' is no list of atoms");
      std::istringstream words(s.substr(at + 1, close - at - 1));
      Atom a;
      if (!(words >> a.predicate)) fail(field + ": an empty atom");
      for (std::string w; words >> w;) a.arguments.push_back(w);
      atoms.push_back(std::move(a));
      at = close + 1;
    }
    return atoms;
  };
  if (!std::getline(in, line) || line != "behaviour,parameters,seed,label,features,changes,atoms_before,atoms_after") {
    number = 1;
    fail("not a file of effect trials (its header differs)");
  }
  number = 1;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty()) continue;
    const auto fields = split(line, ',');
    if (fields.size() != 8) fail("8 fields expected, found " + std::to_string(fields.size()));
    auto it = std::find_if(out.begin(), out.end(), [&](const BehaviourTrials& b) { return b.behaviour == fields[0]; });
    const bool first = it == out.end();
    if (first) {
      out.push_back({});
      it = out.end() - 1;
      it->behaviour = fields[0];
      for (const auto& p : split(fields[1], ';')) {
        const auto dash = p.find(" - ");
        if (dash == std::string::npos) fail("parameters: '" + p + "' is no '?name - type'");
        it->parameters.push_back({p.substr(0, dash), p.substr(dash + 3)});
      }
    }
    EffectTrial t;
    t.seed = static_cast<std::uint64_t>(number_of(fields[2], "seed"));
    t.label = fields[3];
    std::vector<Feature> features;
    for (const auto& f : fields[4].empty() ? std::vector<std::string>{} : split(fields[4], ';')) {
      const auto colon = f.find(':'), equals = f.find('=');
      if (colon == std::string::npos || equals == std::string::npos || equals < colon)
        fail("features: '" + f + "' is no 'name:?parameter=value'");
      features.push_back({f.substr(0, colon), f.substr(colon + 1, equals - colon - 1)});
      t.before.push_back(number_of(f.substr(equals + 1), "features"));
    }
    std::vector<Change> changes;
    for (const auto& c : fields[5].empty() ? std::vector<std::string>{} : split(fields[5], ';')) {
      const auto at = c.find('@'), equals = c.find('=');
      if (at == std::string::npos || equals == std::string::npos || equals < at)
        fail("changes: '" + c + "' is no 'name@resolution=value'");
      changes.push_back({c.substr(0, at), number_of(c.substr(at + 1, equals - at - 1), "changes")});
      t.change.push_back(number_of(c.substr(equals + 1), "changes"));
    }
    if (first) {
      it->features = features;
      it->changes = changes;
    } else {
      const auto same_features = features.size() == it->features.size() &&
          std::equal(features.begin(), features.end(), it->features.begin(),
                     [](const Feature& a, const Feature& b) { return a.name == b.name && a.parameter == b.parameter; });
      const auto same_changes = changes.size() == it->changes.size() &&
          std::equal(changes.begin(), changes.end(), it->changes.begin(),
                     [](const Change& a, const Change& b) { return a.name == b.name && a.resolution == b.resolution; });
      if (!same_features || !same_changes) fail("its features or changes differ from the first row of " + it->behaviour);
    }
    t.atoms_before = atoms_of(fields[6], "atoms_before");
    t.atoms_after = atoms_of(fields[7], "atoms_after");
    it->trials.push_back(std::move(t));
  }
  return out;
}

void save_thresholds(const std::vector<Threshold>& thresholds, const std::string& path) {
  try {
    cv::FileStorage fs(path, cv::FileStorage::WRITE);
    if (!fs.isOpened()) throw pddl::PddlError(path + ": cannot be written");
    fs << "thresholds" << "[";
    for (const auto& t : thresholds)
      fs << "{" << "predicate" << t.predicate << "feature" << t.feature << "type" << t.type << "value" << t.value << "}";
    fs << "]";
  } catch (const cv::Exception& e) {
    throw pddl::PddlError(path + ": cannot be written: " + e.what());
  }
}

std::vector<Threshold> load_thresholds(const std::string& path) {
  std::vector<Threshold> out;
  try {
    cv::FileStorage fs(path, cv::FileStorage::READ);
    if (!fs.isOpened()) throw pddl::PddlError(path + ": cannot be read");
    const cv::FileNode list = fs["thresholds"];
    if (!list.isSeq()) throw pddl::PddlError(path + ": no list 'thresholds'");
    for (const auto& n : list) {
      Threshold t;
      t.predicate = static_cast<std::string>(n["predicate"]);
      t.feature = static_cast<std::string>(n["feature"]);
      t.type = static_cast<std::string>(n["type"]);
      t.value = static_cast<double>(n["value"]);
      if (t.predicate.empty() || t.feature.empty() || t.type.empty() || !std::isfinite(t.value))
        throw pddl::PddlError(path + ": threshold " + std::to_string(out.size() + 1) +
                              " lacks its predicate, feature, type or a finite value");
      out.push_back(std::move(t));
    }
  } catch (const cv::Exception& e) {
    throw pddl::PddlError(path + ": cannot be read: " + e.what());
  }
  return out;
}

std::vector<Atom> threshold_atoms(const pddl::Domain& domain, const std::vector<Threshold>& thresholds,
                                  const std::vector<PerceivedObject>& objects) {
  std::vector<Atom> out;
  for (const auto& o : objects)
    for (const auto& t : thresholds) {
      if (!pddl::is_a(domain, o.type, t.type)) continue;
      const auto f = o.features.find(t.feature);
      if (f != o.features.end() && f->second <= t.value) out.push_back({t.predicate, {o.name}});
    }
  return out;
}

}  // namespace macsim::affordances
