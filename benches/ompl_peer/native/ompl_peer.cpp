// The C++ side of the native OMPL comparison (docs/sampler.md, "Native peer: OMPL's ABIT* and
// BIT*"; run by benches/ompl_peer/native.sh): OMPL's own ABIT* or BIT* (Debian's libompl-dev)
// on one JSON obstacle world of benches/ompl_peer/worlds, with a state validity checker of the
// same semantics as rappel's `ObstacleWorld` (closed bounds, closed boxes, closed balls; OMPL's
// discrete motion validator at the world's resolution), counting its calls.
//
//   ompl_peer header BUDGET_S
//   ompl_peer run WORLD.json abit|bit SEED BUDGET_S [PATH_OUT]
//   ompl_peer verify WORLD.json PATH_FILE
//
// `run` plans once (one process per seed: OMPL's RNG::setSeed works once per process) until
// the process has used BUDGET_S of CPU time and prints one TSV row in the format of
// `sampler_peer native` (the Rust side): CPU and wall time, state checks and batches sampled to
// the first solution, the best cost at fixed CPU-time checkpoints, the final cost, and whether
// the final path passes an independent re-check (every segment's states at the world's
// resolution, cost equal to the path length). `verify` re-checks a path file written by either side.
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/StateValidityChecker.h>
#include <ompl/base/objectives/PathLengthOptimizationObjective.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/planners/informedtrees/ABITstar.h>
#include <ompl/geometric/planners/informedtrees/BITstar.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace ob = ompl::base;
namespace og = ompl::geometric;
using json = nlohmann::json;

namespace
{
    // CPU-time checkpoints (ms) of the cost table, shared with benches/examples/sampler_peer.rs;
    // those up to the budget are printed.
    const std::vector<double> CHECKPOINTS_MS = {10, 30, 100, 300, 1000, 3000, 10000};

    // The ptc reads the CPU clock (a system call) once per this many evaluations, as the Rust
    // side reads it once per this many iterations.
    const unsigned CLOCK_EVERY = 64;

    // Relative tolerance of "the reported cost is the path's length" (summation order differs).
    const double COST_TOLERANCE = 1e-9;

    struct Box
    {
        std::vector<double> min, max;
    };
    struct Ball
    {
        std::vector<double> centre;
        double radius;
    };
    struct World
    {
        std::string name;
        std::size_t d = 0;
        std::vector<double> lo, hi, start, goal;
        std::vector<Box> boxes;
        std::vector<Ball> balls;
        double resolution = 0;
    };

    [[noreturn]] void fail(const std::string &what)
    {
        throw std::runtime_error(what);
    }

    void only_fields(const json &j, const std::set<std::string> &known, const std::string &where)
    {
        if (!j.is_object())
            fail(where + ": expected an object");
        for (auto it = j.begin(); it != j.end(); ++it)
            if (known.count(it.key()) == 0)
                fail(where + ": unknown field `" + it.key() + "`");
    }

    const json &field(const json &j, const std::string &key, const std::string &where)
    {
        auto it = j.find(key);
        if (it == j.end())
            fail(where + ": missing field `" + key + "`");
        return *it;
    }

    double number(const json &j, const std::string &where)
    {
        if (!j.is_number())
            fail(where + ": expected a number");
        double v = j.get<double>();
        if (!std::isfinite(v))
            fail(where + ": non-finite number");
        return v;
    }

    std::vector<double> vec(const json &j, std::size_t d, const std::string &where)
    {
        if (!j.is_array())
            fail(where + ": expected an array");
        if (d != 0 && j.size() != d)
            fail(where + ": expected " + std::to_string(d) + " coordinates, found " + std::to_string(j.size()));
        std::vector<double> v;
        for (std::size_t i = 0; i < j.size(); ++i)
            v.push_back(number(j[i], where + "[" + std::to_string(i) + "]"));
        return v;
    }

    // The world file, checked as rappel's `WorldFile::to_world` checks it; unknown fields are errors.
    World load(const std::string &path)
    {
        std::ifstream in(path);
        if (!in)
            fail(path + ": cannot open");
        json j;
        try
        {
            j = json::parse(in);
        }
        catch (const json::exception &e)
        {
            fail(path + ": " + e.what());
        }
        only_fields(j, {"name", "lo", "hi", "boxes", "spheres", "start", "goal", "resolution"}, path);
        World w;
        const json &name = field(j, "name", path);
        if (!name.is_string())
            fail(path + ": name: expected a string");
        w.name = name.get<std::string>();
        w.lo = vec(field(j, "lo", path), 0, "lo");
        w.d = w.lo.size();
        if (w.d != 2 && w.d != 3)
            fail(path + ": lo: " + std::to_string(w.d) + " dimensions, only 2 and 3 are supported");
        w.hi = vec(field(j, "hi", path), w.d, "hi");
        for (std::size_t i = 0; i < w.d; ++i)
            if (!(w.lo[i] < w.hi[i]))
                fail(path + ": lo/hi: bounds must have lo < hi on every axis");
        if (j.contains("boxes"))
        {
            const json &bs = j["boxes"];
            if (!bs.is_array())
                fail(path + ": boxes: expected an array");
            for (std::size_t i = 0; i < bs.size(); ++i)
            {
                std::string at = "boxes[" + std::to_string(i) + "]";
                only_fields(bs[i], {"min", "max"}, at);
                Box b{vec(field(bs[i], "min", at), w.d, at + ".min"), vec(field(bs[i], "max", at), w.d, at + ".max")};
                for (std::size_t k = 0; k < w.d; ++k)
                    if (b.min[k] > b.max[k])
                        fail(path + ": " + at + ": min > max on some axis");
                w.boxes.push_back(b);
            }
        }
        if (j.contains("spheres"))
        {
            const json &ss = j["spheres"];
            if (!ss.is_array())
                fail(path + ": spheres: expected an array");
            for (std::size_t i = 0; i < ss.size(); ++i)
            {
                std::string at = "spheres[" + std::to_string(i) + "]";
                only_fields(ss[i], {"centre", "radius"}, at);
                Ball b{vec(field(ss[i], "centre", at), w.d, at + ".centre"),
                       number(field(ss[i], "radius", at), at + ".radius")};
                if (!(b.radius > 0))
                    fail(path + ": " + at + ".radius: not a positive finite radius");
                w.balls.push_back(b);
            }
        }
        w.start = vec(field(j, "start", path), w.d, "start");
        w.goal = vec(field(j, "goal", path), w.d, "goal");
        w.resolution = number(field(j, "resolution", path), "resolution");
        if (!(w.resolution > 0 && w.resolution <= 1))
            fail(path + ": resolution: not in (0, 1]");
        return w;
    }

    // rappel's `ObstacleWorld::state_valid`, operation for operation: in the closed bounds and
    // in no closed box or closed ball (squared distance <= radius * radius).
    bool state_valid(const World &w, const double *p)
    {
        for (std::size_t i = 0; i < w.d; ++i)
            if (!(p[i] >= w.lo[i] && p[i] <= w.hi[i]))
                return false;
        for (const Box &b : w.boxes)
        {
            bool inside = true;
            for (std::size_t i = 0; i < w.d && inside; ++i)
                inside = p[i] >= b.min[i] && p[i] <= b.max[i];
            if (inside)
                return false;
        }
        for (const Ball &b : w.balls)
        {
            double s = 0.0;
            for (std::size_t i = 0; i < w.d; ++i)
                s += (p[i] - b.centre[i]) * (p[i] - b.centre[i]);
            if (s <= b.radius * b.radius)
                return false;
        }
        return true;
    }

    // The checker OMPL calls (for samples, start and goal, and through its
    // DiscreteMotionValidator for motions), counting every call.
    class CountingChecker : public ob::StateValidityChecker
    {
    public:
        CountingChecker(const ob::SpaceInformationPtr &si, const World &w) : ob::StateValidityChecker(si), w_(w)
        {
        }
        bool isValid(const ob::State *s) const override
        {
            ++checks;
            return state_valid(w_, s->as<ob::RealVectorStateSpace::StateType>()->values);
        }
        mutable std::uint64_t checks = 0;

    private:
        const World &w_;
    };

    double diagonal(const World &w)
    {
        double s = 0.0;
        for (std::size_t i = 0; i < w.d; ++i)
            s += (w.hi[i] - w.lo[i]) * (w.hi[i] - w.lo[i]);
        return std::sqrt(s);
    }

    double distance(const std::vector<double> &a, const std::vector<double> &b)
    {
        double s = 0.0;
        for (std::size_t i = 0; i < a.size(); ++i)
            s += (a[i] - b[i]) * (a[i] - b[i]);
        return std::sqrt(s);
    }

    // The independent re-check of a path (not OMPL's validator, not counted): starts at the
    // start, ends at the goal, every state valid, and every segment's states at `j / n`,
    // `n = ceil(length / (resolution * diagonal))`, valid in plain order. Returns the error or "".
    std::string check_path(const World &w, const std::vector<std::vector<double>> &path, double cost)
    {
        if (path.size() < 2)
            return "fewer than two states";
        if (path.front() != w.start)
            return "does not start at the start";
        if (path.back() != w.goal)
            return "does not end at the goal";
        double step = w.resolution * diagonal(w), length = 0.0;
        for (std::size_t k = 0; k < path.size(); ++k)
        {
            if (path[k].size() != w.d)
                return "state " + std::to_string(k) + " has the wrong dimension";
            if (!state_valid(w, path[k].data()))
                return "state " + std::to_string(k) + " is invalid";
            if (k == 0)
                continue;
            const auto &a = path[k - 1], &b = path[k];
            double len = distance(a, b);
            length += len;
            auto n = static_cast<std::size_t>(std::ceil(len / step));
            std::vector<double> p(w.d);
            for (std::size_t j = 1; j < n; ++j)
            {
                double t = static_cast<double>(j) / static_cast<double>(n);
                for (std::size_t i = 0; i < w.d; ++i)
                    p[i] = a[i] + (b[i] - a[i]) * t;
                if (!state_valid(w, p.data()))
                    return "segment " + std::to_string(k) + " is invalid at " + std::to_string(j) + "/" +
                           std::to_string(n);
            }
        }
        if (!(std::fabs(length - cost) <= COST_TOLERANCE * std::max(1.0, length)))
        {
            std::ostringstream o;
            o.precision(17);
            o << "reported cost " << cost << " differs from the path length " << length;
            return o.str();
        }
        return "";
    }

    double cpu_now()
    {
        timespec ts{};
        if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) != 0)
            fail("clock_gettime(CLOCK_PROCESS_CPUTIME_ID) failed");
        return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
    }

    double wall_now()
    {
        timespec ts{};
        if (clock_gettime(CLOCK_MONOTONIC, &ts) != 0)
            fail("clock_gettime(CLOCK_MONOTONIC) failed");
        return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
    }

    std::vector<double> checkpoints(double budget_s)
    {
        std::vector<double> out;
        for (double c : CHECKPOINTS_MS)
            if (c <= budget_s * 1000.0 + 1e-9)
                out.push_back(c);
        return out;
    }

    std::string header(double budget_s)
    {
        std::string h = "side\tplanner\tworld\tseed\tsolved\tfirst_cpu_ms\tfirst_wall_ms\tchecks_first\tcost_first"
                        "\tbatches_first";
        for (double c : checkpoints(budget_s))
        {
            std::ostringstream o;
            o << "\tc@" << c << "ms";
            h += o.str();
        }
        return h + "\tfinal_cost\tchecks_total\tcpu_total_ms\tpath_states\tpath_check";
    }

    std::string fmt(double v, int prec)
    {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.*f", prec, v);
        return buf;
    }

    double parse_double(const std::string &s, const std::string &what)
    {
        std::size_t used = 0;
        double v = 0;
        try
        {
            v = std::stod(s, &used);
        }
        catch (const std::exception &)
        {
            fail(what + ": `" + s + "` is not a number");
        }
        if (used != s.size() || !std::isfinite(v))
            fail(what + ": `" + s + "` is not a finite number");
        return v;
    }

    struct Event
    {
        double cpu, cost;
    };

    int run(const std::string &world_path, const std::string &planner_name, const std::string &seed_s,
            const std::string &budget_s_s, const std::string &path_out)
    {
        double seed_d = parse_double(seed_s, "SEED");
        if (!(seed_d >= 1 && seed_d <= 4294967295.0 && seed_d == std::floor(seed_d)))
            fail("SEED: must be an integer in 1..=4294967295 (OMPL's 0 means a random seed)");
        double budget = parse_double(budget_s_s, "BUDGET_S");
        if (!(budget > 0))
            fail("BUDGET_S: must be positive");
        if (planner_name != "abit" && planner_name != "bit")
            fail("PLANNER: `" + planner_name + "` is neither abit nor bit");
        // Before any RNG exists (OMPL: effective once per process).
        ompl::RNG::setSeed(static_cast<std::uint_fast32_t>(seed_d));
        ompl::msg::setLogLevel(ompl::msg::LOG_ERROR);
        World w = load(world_path);

        auto space = std::make_shared<ob::RealVectorStateSpace>(w.d);
        ob::RealVectorBounds bounds(w.d);
        for (std::size_t i = 0; i < w.d; ++i)
        {
            bounds.setLow(i, w.lo[i]);
            bounds.setHigh(i, w.hi[i]);
        }
        space->setBounds(bounds);
        auto si = std::make_shared<ob::SpaceInformation>(space);
        auto checker = std::make_shared<CountingChecker>(si, w);
        si->setStateValidityChecker(checker);
        // The longest valid segment is resolution * the space's maximum extent (its diagonal):
        // rappel's `ObstacleWorld::step`. SpaceInformation's default motion validator for a
        // real vector space is the DiscreteMotionValidator.
        si->setStateValidityCheckingResolution(w.resolution);
        si->setup();
        ob::ScopedState<> start(space), goal(space);
        for (std::size_t i = 0; i < w.d; ++i)
        {
            start[i] = w.start[i];
            goal[i] = w.goal[i];
        }
        auto pdef = std::make_shared<ob::ProblemDefinition>(si);
        pdef->setStartAndGoalStates(start, goal);
        pdef->setOptimizationObjective(std::make_shared<ob::PathLengthOptimizationObjective>(si));

        std::vector<Event> events;
        // Declared before the callback, which reads the planner's batch count at the first solution.
        std::shared_ptr<og::BITstar> planner;
        unsigned batches_first = 0;
        std::uint64_t checks_first = 0;
        double first_wall = NAN;
        double cpu0 = 0, wall0 = 0;
        // The intermediate-solution callback: BIT* and ABIT* call it on every improvement of the
        // best solution (BITstar::updateGoalVertex), so its clock reads are the exact times.
        pdef->setIntermediateSolutionCallback(
            [&](const ob::Planner *, const std::vector<const ob::State *> &, const ob::Cost cost)
            {
                double cpu = cpu_now() - cpu0;
                if (events.empty())
                {
                    checks_first = checker->checks;
                    batches_first = planner->numBatches();
                    first_wall = wall_now() - wall0;
                }
                events.push_back({cpu, cost.value()});
            });

        // The clock starts before the planner exists (rappel's side: before `Abit::new`), and
        // the counter counts from there (start and goal checks, samples, motions).
        checker->checks = 0;
        cpu0 = cpu_now();
        wall0 = wall_now();
        // Named as OMPL names its k-nearest variants (else it warns and renames them).
        if (planner_name == "abit")
            planner = std::make_shared<og::ABITstar>(si, "kABITstar");
        else
            planner = std::make_shared<og::BITstar>(si, "kBITstar");
        planner->setProblemDefinition(pdef);
        planner->setup();
        unsigned calls = 0;
        double cpu_used = 0;
        ob::PlannerTerminationCondition ptc(
            [&]
            {
                if (++calls % CLOCK_EVERY != 0)
                    return false;
                cpu_used = cpu_now() - cpu0;
                return cpu_used >= budget;
            });
        planner->solve(ptc);
        double cpu_total = cpu_now() - cpu0;
        std::uint64_t checks_total = checker->checks;

        bool solved = pdef->hasExactSolution() && !events.empty();
        std::vector<std::vector<double>> path;
        double final_cost = NAN;
        std::string path_check = "-";
        if (solved)
        {
            final_cost = planner->bestCost().value();
            auto p = pdef->getSolutionPath()->as<og::PathGeometric>();
            for (std::size_t k = 0; k < p->getStateCount(); ++k)
            {
                const double *v = p->getState(k)->as<ob::RealVectorStateSpace::StateType>()->values;
                path.emplace_back(v, v + w.d);
            }
            if (final_cost != events.back().cost)
                path_check = "best cost differs from the last reported improvement";
            else
            {
                std::string e = check_path(w, path, final_cost);
                path_check = e.empty() ? "ok" : e;
            }
            if (!path_out.empty())
            {
                std::ofstream out(path_out);
                out.precision(17);
                out << "cost " << final_cost << "\n";
                for (const auto &s : path)
                {
                    for (std::size_t i = 0; i < w.d; ++i)
                        out << (i ? " " : "") << s[i];
                    out << "\n";
                }
                if (!out)
                    fail(path_out + ": write failed");
            }
        }

        std::ostringstream row;
        row << "ompl\t" << planner_name << "\t" << w.name << "\t" << seed_s << "\t" << (solved ? "yes" : "no");
        if (solved)
            row << "\t" << fmt(events.front().cpu * 1e3, 4) << "\t" << fmt(first_wall * 1e3, 4) << "\t"
                << checks_first << "\t" << fmt(events.front().cost, 6) << "\t" << batches_first;
        else
            row << "\t-\t-\t-\t-\t-";
        for (double c : checkpoints(budget))
        {
            double best = NAN;
            for (const Event &e : events)
                if (e.cpu * 1e3 <= c)
                    best = e.cost;
            row << "\t" << (std::isnan(best) ? std::string("-") : fmt(best, 6));
        }
        row << "\t" << (solved ? fmt(final_cost, 6) : "-") << "\t" << checks_total << "\t" << fmt(cpu_total * 1e3, 1)
            << "\t" << path.size() << "\t" << path_check;
        std::cout << row.str() << std::endl;
        return path_check == "ok" || !solved ? 0 : 1;
    }

    // Reads a path file (`cost C`, then one state per line) and re-checks it.
    int verify(const std::string &world_path, const std::string &path_file)
    {
        World w = load(world_path);
        std::ifstream in(path_file);
        if (!in)
            fail(path_file + ": cannot open");
        std::string line, word;
        if (!std::getline(in, line))
            fail(path_file + ": empty");
        std::istringstream first(line);
        double cost = 0;
        if (!(first >> word >> cost) || word != "cost" || !(first >> std::ws).eof())
            fail(path_file + ": line 1: expected `cost C`");
        std::vector<std::vector<double>> path;
        for (std::size_t n = 2; std::getline(in, line); ++n)
        {
            std::istringstream l(line);
            std::vector<double> s;
            double v = 0;
            while (l >> v)
                s.push_back(v);
            if (!(l.eof()) || s.size() != w.d)
                fail(path_file + ": line " + std::to_string(n) + ": expected " + std::to_string(w.d) + " numbers");
            path.push_back(s);
        }
        std::string e = check_path(w, path, cost);
        if (!e.empty())
        {
            std::cerr << "error: " << path_file << ": " << e << "\n";
            return 1;
        }
        return 0;
    }
}  // namespace

int main(int argc, char **argv)
{
    std::vector<std::string> a(argv + 1, argv + argc);
    try
    {
        if (a.size() == 2 && a[0] == "header")
        {
            std::cout << header(parse_double(a[1], "BUDGET_S")) << std::endl;
            return 0;
        }
        if ((a.size() == 5 || a.size() == 6) && a[0] == "run")
            return run(a[1], a[2], a[3], a[4], a.size() == 6 ? a[5] : "");
        if (a.size() == 3 && a[0] == "verify")
            return verify(a[1], a[2]);
        std::cerr << "usage: ompl_peer header BUDGET_S | run WORLD.json abit|bit SEED BUDGET_S [PATH_OUT] | "
                     "verify WORLD.json PATH_FILE\n";
        return 2;
    }
    catch (const std::exception &e)
    {
        std::cerr << "error: " << e.what() << "\n";
        return 2;
    }
}
