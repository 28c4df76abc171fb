// Effects learned from a behaviour's trials: the perceived changes grouped into effect categories
// by k-means (the count chosen by the silhouette), a decision tree that predicts the category from what was
// perceived before, and a planning domain read off both (pddl.h): an operator per leaf, its
// preconditions the leaf's path, its outcomes the categories met there with their shares.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "macsim/affordances/pddl.h"

namespace macsim::affordances {

/// One trial of a behaviour, as the robot perceived it.
struct EffectTrial {
  std::uint64_t seed = 0;
  std::string label;           ///< the trial runner's label (world state): reported, never learned
  std::vector<double> before;  ///< features before, in BehaviourTrials::features' order
  std::vector<double> change;  ///< the perceived change, in BehaviourTrials::changes' order
  /// The scene's atoms before and after, their arguments the behaviour's parameters (`?t`).
  std::vector<pddl::Atom> atoms_before, atoms_after;
};

/// A perceived feature of what one of the behaviour's parameters names (`hue` of `?t`).
struct Feature {
  std::string name;
  std::string parameter;
};

/// A perceived change (m, rad) and the least change the robot's sensors tell from none.
struct Change {
  std::string name;
  double resolution = 0.01;
};

/// Every trial of one behaviour and what its columns are.
struct BehaviourTrials {
  std::string behaviour;                  ///< e.g. "lift"
  std::vector<pddl::Typed> parameters;    ///< e.g. ?t - thing
  std::vector<Feature> features;          ///< of `before`
  std::vector<Change> changes;            ///< of `change`
  std::vector<EffectTrial> trials;
};

/// "feature <= value" of an object of `type`, as a predicate: `hue-le-214p5`.
struct Threshold {
  std::string predicate;
  std::string feature;
  std::string type;
  double value = 0;
};

/// The least mean silhouette (Kaufman and Rousseeuw: "a reasonable structure") for which the
/// changes count as more than one category.
inline constexpr double kClearSilhouette = 0.5;

/// The effect categories of one behaviour.
struct EffectCategories {
  int count = 0;                           ///< k
  std::vector<double> silhouette;          ///< mean silhouette for k = 2, 3, ... as tried
  std::vector<int> of_trial;               ///< category of each trial, 0 the commonest
  std::vector<std::vector<double>> centres;  ///< mean change per category, in `changes` units
  std::vector<pddl::Outcome> effects;      ///< per category: the atoms most of its trials changed
  /// How the categories match the runner's labels: trials per (category, label), and the
  /// adjusted Rand index (1: the same partition; about 0: unrelated).
  std::map<std::pair<int, std::string>, int> with_label;
  double adjusted_rand = 0;
};

/// One condition on the way from a tree's root to a leaf: a feature at most (or above) a value,
/// or an atom that holds (or not).
struct Condition {
  int feature = -1;  ///< index into the tree's inputs (BehaviourTrials::features, then atoms)
  double value = 0;
  bool at_most = true;  ///< feature <= value (else >)
};

/// A leaf of a behaviour's tree as a rule: its conditions, the category it predicts, and how
/// often each category fell there in the training trials.
struct Rule {
  std::vector<Condition> conditions;
  int category = 0;
  std::map<int, int> trials_per_category;
};

/// What was learned of one behaviour.
struct LearnedBehaviour {
  std::string behaviour;
  EffectCategories categories;
  std::vector<std::string> inputs;  ///< the tree's inputs: the features, then the atoms (0/1)
  std::vector<pddl::Atom> input_atoms;  ///< the atoms among the inputs
  std::vector<Rule> rules;
  double held_out_accuracy = 0;  ///< of the tree fitted on the other trials
  int held_out_trials = 0;
  std::vector<pddl::Atom> always_before;  ///< atoms that held before every trial
  /// Atoms the trials made true but that held before none of them (a lift never began holding
  /// the thing or with it tried): what was never seen is not counted on, so they must not hold.
  std::vector<pddl::Atom> never_before;
};

/// Drops from each trial's atoms those the vocabulary's predicates cannot say of the behaviour's
/// parameters: an unknown predicate, another arity, or a parameter of a type the predicate does
/// not take (`(open ?from)` where ?from is any location and open takes a door). What is left is
/// what a learned operator may require and change.
void keep_typed_atoms(const pddl::Domain& vocabulary, BehaviourTrials& trials);

/// Groups the trials' perceived changes into categories: each column in units of its resolution,
/// k-means (k-means++ seeded, 5 attempts) for k = 2..max_k, of those whose centres lie a
/// resolution apart at least the k of the largest mean silhouette if it reaches kClearSilhouette
/// (clearly separate groups), else one category. Deterministic.
EffectCategories categorise(const BehaviourTrials& trials, int max_k = 6);

/// The effect categories, a decision tree over the features and the atoms before (held-out
/// accuracy on 30 % of the seeds, then refit on all), and its leaves as rules.
LearnedBehaviour learn_behaviour(const BehaviourTrials& trials, int max_k = 6);

/// The rule whose conditions hold for one trial's features and atoms before (each trial's inputs
/// meet exactly one rule).
const Rule& rule_for(const LearnedBehaviour& learned, const std::vector<double>& before,
                     const std::vector<pddl::Atom>& atoms_before);

/// A learned domain: the shared vocabulary (types and the scene's predicates) and an operator
/// per rule of each behaviour, its outcomes with probabilities; the thresholds it introduced.
struct LearnedDomain {
  pddl::Domain domain;
  std::vector<Threshold> thresholds;
};

/// The domain read off the learned behaviours. `vocabulary` gives the name, the types and the
/// scene's predicates (its operators are ignored).
LearnedDomain learned_domain(const pddl::Domain& vocabulary,
                             const std::vector<BehaviourTrials>& trials,
                             const std::vector<LearnedBehaviour>& learned);

/// A thing or place as perceived: its name and type in a problem, its features by name.
struct PerceivedObject {
  std::string name;
  std::string type;
  std::map<std::string, double> features;
};

/// The atoms of `thresholds` that hold for these objects: `(hue-le-214p5 can-1)` where the
/// object's type is the threshold's (or derives from it in `domain`) and its feature is at most
/// the value. An object without the feature gets none of its atoms.
std::vector<pddl::Atom> threshold_atoms(const pddl::Domain& domain,
                                        const std::vector<Threshold>& thresholds,
                                        const std::vector<PerceivedObject>& objects);

/// Trials as CSV text, a row per trial: behaviour, its parameters, seed, label, the features
/// before, the changes (each with its resolution), the atoms before and after. Numbers are written
/// to round-trip exactly, so that what is learned from the text equals what was learned from the
/// trials.
std::string write_effect_trials(const std::vector<BehaviourTrials>& trials);
/// Reads what write_effect_trials wrote (behaviours in order of first appearance); throws
/// pddl::PddlError naming `file`, the line and the field.
std::vector<BehaviourTrials> read_effect_trials(const std::string& text, const std::string& file);

/// The thresholds a learned domain introduced, as a file (OpenCV's FileStorage, YAML) and back;
/// both throw pddl::PddlError naming the file.
void save_thresholds(const std::vector<Threshold>& thresholds, const std::string& path);
std::vector<Threshold> load_thresholds(const std::string& path);

/// The predicate name of "feature <= value": `hue-le-214p5`, `slope-le-m0p25`.
std::string threshold_predicate(const std::string& feature, double value);

}  // namespace macsim::affordances
