#include "solver_table.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

namespace cloth {

namespace {

std::vector<SolverKey> exactKeys(bool withMethod) {
    using E = ExactSettings;
    using namespace keys;
    std::vector<SolverKey> own;
    if (withMethod)
        own.push_back(shown(choice<E, E::Method>(
            "method", &E::method, {{"cholesky", E::Method::Cholesky}, {"cg", E::Method::CG}, {"multigrid", E::Method::Multigrid}},
            "how the system is solved")));
    else
        own.push_back(integer<E>("iterations", &E::iterations, 0, 1000000,
                                 "a fixed number of iterations, an approximation; 0 = until the tolerance"));
    own.push_back(shown(real<E>("tolerance", &E::tolerance, 0, 1, true, true,
                                "relative residual the solve must reach, else the step fails")));
    own.push_back(integer<E>("max_iterations", &E::maxIterations, 1, 1000000,
                             "cg: iterations; multigrid: cycles (at most 1000)"));
    return with(std::move(own), true);
}

void cgDefaults(SolverConfig& c) {
    ExactSettings s;
    s.method = ExactSettings::Method::CG;
    c.settings = s;
}

// multigrid's own keys: what a user chooses. Its tuning (MultigridTuning) is not a key.
std::vector<SolverKey> multigridKeys() {
    using M = MultigridSettings;
    using namespace keys;
    using P = M::Precision;
    return with({shown(integer<M>("cycles", &M::cycles, 0, 1000, "fixed cycles; 0 = adaptive (tolerance, max_cycles)")),
                 real<M>("tolerance", &M::tolerance, 0, 1, true, true, "adaptive: relative residual to reach"),
                 integer<M>("max_cycles", &M::maxCycles, 1, 1000, "adaptive: at most this many cycles"),
                 integer<M>("threads", &M::threads, 1, 64, "worker threads (bit-identical results for any count)"),
                 choice<M, P>("precision", &M::precision,
                              {{"double", P::Double}, {"mixed", P::Mixed}, {"float", P::Float}},
                              "arithmetic of the solve (the state stays double); mixed: float cycles "
                              "preconditioning a double CG")},
                true);
}

std::string multigridCheck(const SolverConfig& c) {
    const MultigridSettings& s = c.get<MultigridSettings>();
    if (s.precision == MultigridSettings::Precision::Float && s.tolerance < 1e-6)
        return "solver 'multigrid' parameter tolerance = " + std::to_string(s.tolerance) +
               " is below what precision=float can reach (>= 1e-6)";
    if (!s.tuning) return {};
    if (s.tuning->preSweeps + s.tuning->postSweeps == 0)
        return "solver 'multigrid': its tuning has no smoothing sweeps (pre + post must be at least 1)";
    if (s.precision == MultigridSettings::Precision::Mixed && !s.tuning->krylov)
        return "solver 'multigrid' parameter precision = mixed needs its tuning's CG (the double CG corrects the "
               "float cycles)";
    return {};
}

}  // namespace

// The solver table: every kind with its keys. Rows are name, type, range, default (from the
// settings struct), doc.
const std::vector<SolverKind>& solverKinds() {
    using namespace keys;
    using K = KangChoSettings;
    using C = ChebyshevSettings;
    using X = ExplicitSettings;
    using N = NewtonSettings;
    using P = XpbdSettings;
    static const std::vector<SolverKind> kinds = {
        {"kangcho", "the paper: dv(0) and Jacobi sweeps of the linearized backward Euler system (eqs. 11, 14)",
         defaultsTo<K>,
         with(std::vector<SolverKey>{
                  shown(integer<K>("iterations", &K::iterations, 0, 100000, "Jacobi sweeps after dv(0); 1 = the paper's step")),
                  choice<K, K::Impl>("impl", &K::impl,
                                     {{"fast", K::Impl::Fast}, {"gather", K::Impl::Gather}, {"reference", K::Impl::Reference}},
                                     "fast: stencil layout on grids, else gather; reference: the paper's step as written")} +
                  parallel<K>("arithmetic of the step (the state stays double)"),
              true),
         {}, makeKangChoSolver},
        {"exact", "the same system solved to a tolerance: the reference", defaultsTo<ExactSettings>, exactKeys(true), {},
         makeExactSolver},
        {"cg", "exact with method=cg: conjugate gradients, diagonal preconditioner", cgDefaults, exactKeys(false), {},
         makeExactSolver},
        {"multigrid", "multigrid cycles on the same system (damped Jacobi smoother, Galerkin coarse levels), as CG's preconditioner",
         defaultsTo<MultigridSettings>, multigridKeys(), multigridCheck, makeMultigridSolver},
        {"chebyshev", "Jacobi with Chebyshev semi-iterative acceleration (Wang 2015)", defaultsTo<C>,
         with({shown(integer<C>("iterations", &C::iterations, 0, 100000, "accelerated Jacobi sweeps after dv(0)")),
               real<C>("rho", &C::rho, 0, 1, false, true, "Jacobi spectral radius; 0 = estimated each step")},
              true),
         {}, makeChebyshevSolver},
        {"desbrun", "Desbrun, Schroder & Barr 1999: constant isotropic Jacobian, factored once",
         defaultsTo<DesbrunSettings>, common(false), {}, makeDesbrunSolver},
        {"explicit", "symplectic Euler: v += h f / m, x += h v, in substeps", defaultsTo<X>,
         with({shown(integer<X>("substeps", &X::substeps, 1, 100000, "substeps per step"))}, false), {},
         makeExplicitSolver},
        {"newton", "the implicit step converged: Newton iterations, GMRES with multigrid, the air fully coupled",
         defaultsTo<N>,
         with({shown(choice<N, N::Integrator>("integrator", &N::integrator,
                                              {{"be", N::Integrator::BackwardEuler}, {"bdf2", N::Integrator::BDF2},
                                               {"midpoint", N::Integrator::Midpoint}},
                                              "backward Euler; BDF2 (Choi & Ko 2002; its first step backward Euler); theta-midpoint")),
               real<N>("theta", &N::theta, 0.5, 1, false, false, "midpoint: forces at x_n + theta h u; 1/2 damps no mode, 1 is backward Euler"),
               integer<N>("max_iterations", &N::maxIterations, 1, 100, "Newton iterations per step; 1 = the linearized step"),
               real<N>("tolerance", &N::tolerance, 0, 1e3, true, false, "stop when the last iteration changed no velocity by more (m/s)"),
               real<N>("linear_tolerance", &N::linearTolerance, 0, 1, true, true, "relative residual of each linear solve"),
               choice<N, bool>("air", &N::coupledAir, {{"coupled", true}, {"frozen", false}},
                               "coupled: the air at every iterate, its whole derivative; frozen: the air at the step's start, its drag implicit in velocity"),
               integer<N>("threads", &N::threads, 1, 64, "worker threads (bit-identical results for any count)")},
              true),
         {}, makeNewtonSolver},
        {"xpbd", "the springs as compliant constraints (compliance 1/k), Gauss-Seidel projection; in small steps",
         defaultsTo<P>,
         with({shown(integer<P>("iterations", &P::iterations, 1, 10000, "passes over the springs per step")),
               shown(choice<P, bool>("chains", &P::chains, {{"on", true}, {"off", false}},
                                     "on: a grid's rows and columns of structural springs each a chain solved at once "
                                     "(tridiagonal), the rest Gauss-Seidel; off: all Gauss-Seidel"))},
              false),
         {}, makeXpbdSolver},
    };
    return kinds;
}

SolverConfig defaultsOf(const SolverKind& kind) {
    SolverConfig c;
    c.name = kind.name;
    kind.defaults(c);
    return c;
}

const SolverKind* findSolverKind(std::string_view name) {
    for (const SolverKind& k : solverKinds())
        if (name == k.name) return &k;
    return nullptr;
}

namespace keys {

std::vector<SolverKey> common(bool implicit) {
    std::vector<SolverKey> out;
    if (implicit)
        out.push_back(shown(choice<SolverConfig, bool>("compression", &SolverConfig::compressionRule,
                                                       {{"on", true}, {"off", false}},
                                                       "eq. 17: under compression the Jacobian uses l0 := L")));
    return out;
}

std::vector<SolverKey> operator+(std::vector<SolverKey> a, std::vector<SolverKey> b) {
    for (SolverKey& k : b) a.push_back(std::move(k));
    return a;
}

std::vector<SolverKey> with(std::vector<SolverKey> own, bool implicit) { return std::move(own) + common(implicit); }

}  // namespace keys

const std::vector<ConstraintKey>& constraintKeys() {
    using namespace keys;
    using C = Constraints;
    static const std::vector<ConstraintKey> rows = {
        real<C>("tether", &C::tether, 0, 10, false, true,
                "tethers (long-range attachments): no particle farther from its nearest pin than (1 + tether) "
                "times at rest (0 = off)"),
        real<C>("stretch_limit", &C::stretchLimit, 0, 10, false, true,
                "the stretch limit: no spring longer than (1 + stretch_limit) times its rest length (0 = off)"),
        integer<C>("stretch_passes", &C::stretchPasses, 1, 1000, "Gauss-Seidel passes of the stretch limit"),
    };
    return rows;
}

namespace {

std::string number(double v) {
    std::ostringstream s;
    s.precision(17);
    s << v;
    // The shortest text that reads back to the same double.
    for (int p = 1; p <= 17; ++p) {
        std::ostringstream t;
        t.precision(p);
        t << v;
        if (std::stod(t.str()) == v) return t.str();
    }
    return s.str();
}

bool parseNumber(std::string_view text, double& out) {
    auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
    return ec == std::errc() && p == text.data() + text.size() && std::isfinite(out);
}

bool fail(std::string* error, const std::string& message) {
    if (error) *error = message;
    return false;
}

// Reads `text` as the key's value (a choice's index); false if it is not one.
bool readValue(const KeyRow& key, std::string_view text, double& value) {
    switch (key.type) {
        case KeyRow::Type::Choice:
            for (std::size_t i = 0; i < key.choices.size(); ++i)
                if (text == key.choices[i]) return value = double(i), true;
            // Switches also take true/false and 1/0.
            if (key.choices.size() == 2 && key.choices[0] == "on") {
                if (text == "true" || text == "1") return value = 0, true;
                if (text == "false" || text == "0") return value = 1, true;
            }
            return false;
        case KeyRow::Type::Integer: {
            int v = 0;
            auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
            if (ec != std::errc() || p != text.data() + text.size()) return false;
            value = v;
            return true;
        }
        case KeyRow::Type::Real: return parseNumber(text, value);
    }
    return false;
}

bool inRange(const KeyRow& key, double v) {
    if (key.type == KeyRow::Type::Choice) return true;
    return (key.minOpen ? v > key.min : v >= key.min) && (key.maxOpen ? v < key.max : v <= key.max);
}

const SolverKey* findKey(const SolverKind& kind, std::string_view name) {
    for (const SolverKey& k : kind.keys)
        if (name == k.name) return &k;
    return nullptr;
}

std::string knownNames() {
    std::string out;
    for (const SolverKind& k : solverKinds()) out += (out.empty() ? "" : ", ") + std::string(k.name);
    return out;
}

}  // namespace

template <class Target>
std::string Key<Target>::text(const Target& c) const {
    const double v = get(c);
    if (type == Type::Choice) return choices[std::size_t(v)];
    if (type == Type::Integer) return std::to_string(int(v));
    return number(v);
}

template struct Key<SolverConfig>;
template struct Key<Constraints>;

std::string KeyRow::range() const {
    if (type == Type::Choice) {
        std::string out;
        for (const std::string& c : choices) out += (out.empty() ? "" : "|") + c;
        return out;
    }
    auto bound = [this](double v) { return type == Type::Integer ? std::to_string(int(v)) : number(v); };
    return std::string(minOpen ? "(" : "[") + bound(min) + ", " + bound(max) + (maxOpen ? ")" : "]");
}

bool defaultSolverConfig(std::string_view name, SolverConfig& out, std::string* error) {
    const SolverKind* kind = findSolverKind(name);
    if (!kind) return fail(error, "unknown solver '" + std::string(name) + "' (known: " + knownNames() + ")");
    out = defaultsOf(*kind);
    return true;
}

bool setSolverParameter(SolverConfig& config, std::string_view key, std::string_view value, std::string* error) {
    const SolverKind* kind = findSolverKind(config.name);
    if (!kind) return fail(error, "unknown solver '" + config.name + "' (known: " + knownNames() + ")");
    const SolverKey* k = findKey(*kind, key);
    if (!k) {
        std::string known;
        for (const SolverKey& row : kind->keys) known += (known.empty() ? "" : ", ") + std::string(row.name);
        return fail(error, "solver '" + config.name + "' has no parameter '" + std::string(key) + "' (known: " + known + ")");
    }
    double v = 0;
    if (!readValue(*k, value, v) || !inRange(*k, v))
        return fail(error, "solver '" + config.name + "' parameter " + std::string(key) + " has a bad value '" +
                               std::string(value) + "' (allowed: " + k->range() + ")");
    k->set(config, v);
    return true;
}

namespace {

// set(key, value) for each "key=value" of a comma-separated list; false at the first item that is
// not key=value (naming it, as a `what`) or that set refuses.
template <class Set>
bool forEachItem(std::string_view list, const char* what, std::string* error, Set&& set) {
    while (!list.empty()) {
        const auto comma = list.find(',');
        const std::string_view item = list.substr(0, comma);
        list = comma == std::string_view::npos ? "" : list.substr(comma + 1);
        const auto eq = item.find('=');
        if (eq == std::string_view::npos) return fail(error, std::string(what) + " '" + std::string(item) + "' is not key=value");
        if (!set(item.substr(0, eq), item.substr(eq + 1))) return false;
    }
    return true;
}

}  // namespace

bool parseSolverConfig(std::string_view spec, SolverConfig& out, std::string* error) {
    const auto colon = spec.find(':');
    SolverConfig c;
    if (!defaultSolverConfig(spec.substr(0, colon), c, error)) return false;
    const std::string_view rest = colon == std::string_view::npos ? "" : spec.substr(colon + 1);
    if (!forEachItem(rest, "solver parameter", error, [&](std::string_view key, std::string_view value) {
            return setSolverParameter(c, key, value, error);
        }))
        return false;
    const std::string problem = validate(c);
    if (!problem.empty()) return fail(error, problem);
    out = std::move(c);
    return true;
}

std::string validate(const SolverConfig& c) {
    const SolverKind* kind = findSolverKind(c.name);
    if (!kind) return "unknown solver '" + c.name + "' (known: " + knownNames() + ")";
    if (c.settings.index() != defaultsOf(*kind).settings.index())
        return "solver '" + c.name + "' holds the settings of another kind";
    for (const SolverKey& k : kind->keys)
        if (!inRange(k, k.get(c)))
            return "solver '" + c.name + "' parameter " + k.name + " = " + k.text(c) + " must be in " + k.range();
    return kind->check ? kind->check(c) : std::string();
}

std::string SolverConfig::describe() const {
    const SolverKind* kind = findSolverKind(name);
    if (!kind) return name;
    const SolverConfig defaults = defaultsOf(*kind);
    std::string out = name;
    char separator = ':';
    for (const SolverKey& k : kind->keys) {
        if (!k.alwaysShown && k.get(*this) == k.get(defaults)) continue;
        out += separator + std::string(k.name) + "=" + k.text(*this);
        separator = ',';
    }
    return out;
}

bool setConstraint(Constraints& c, std::string_view key, std::string_view value, std::string* error) {
    const auto& rows = constraintKeys();
    const auto k = std::find_if(rows.begin(), rows.end(), [&](const ConstraintKey& r) { return key == r.name; });
    if (k == rows.end()) {
        std::string known;
        for (const ConstraintKey& r : rows) known += (known.empty() ? "" : ", ") + std::string(r.name);
        return fail(error, "constraints have no key '" + std::string(key) + "' (known: " + known + ")");
    }
    double v = 0;
    if (!readValue(*k, value, v) || !inRange(*k, v))
        return fail(error, "constraint " + std::string(key) + " has a bad value '" + std::string(value) +
                               "' (allowed: " + k->range() + ")");
    k->set(c, v);
    return true;
}

bool parseConstraints(std::string_view spec, Constraints& out, std::string* error) {
    Constraints c;
    if (!forEachItem(spec, "constraint", error,
                     [&](std::string_view key, std::string_view value) { return setConstraint(c, key, value, error); }))
        return false;
    out = c;
    return true;
}

std::string validate(const Constraints& c) {
    for (const ConstraintKey& k : constraintKeys())
        if (!inRange(k, k.get(c))) return std::string("constraint ") + k.name + " = " + k.text(c) + " must be in " + k.range();
    return {};
}

std::string Constraints::describe() const {
    const Constraints defaults;
    std::string out;
    for (const ConstraintKey& k : constraintKeys())
        if (k.get(*this) != k.get(defaults)) {
            if (!out.empty()) out += ',';
            out.append(k.name).append("=").append(k.text(*this));
        }
    return out;
}

namespace {

// One key's row of the table: plain text or Markdown (a '|' inside a Markdown cell must be
// escaped, even in code).
template <class Target>
void printRow(std::ostringstream& s, const Key<Target>& k, const Target& defaults, bool markdown) {
    std::string range;
    for (const char ch : k.range()) range += markdown && ch == '|' ? std::string("\\|") : std::string(1, ch);
    if (markdown) s << "| | `" << k.name << "` | `" << range << "` | `" << k.text(defaults) << "` | " << k.doc << " |\n";
    else s << "    " << k.name << "=" << range << " (default " << k.text(defaults) << ")  " << k.doc << "\n";
}

// The table as text: plain for --help, or Markdown for the README (a '|' inside a Markdown cell
// must be escaped, even in code).
std::string printTable(bool markdown) {
    std::ostringstream s;
    s << (markdown ? "| solver | key | values | default | what it does |\n|---|---|---|---|---|\n"
                   : "Solvers: name[:key=value,...]\n");
    for (const SolverKind& kind : solverKinds()) {
        const SolverConfig d = defaultsOf(kind);
        if (markdown) s << "| **" << kind.name << "** | | | | " << kind.doc << " |\n";
        else s << "\n  " << kind.name << "  " << kind.doc << "\n";
        for (const SolverKey& k : kind.keys) printRow(s, k, d, markdown);
    }
    const char* what = "the cloth's corrections after any solver's step (a scene's flag.constraints, --constraints)";
    if (markdown) s << "| **constraints** | | | | " << what << " |\n";
    else s << "\nConstraints: key=value,...  " << what << "\n";
    for (const ConstraintKey& k : constraintKeys()) printRow(s, k, Constraints{}, markdown);
    return s.str();
}

}  // namespace

std::vector<std::string> solverKindNames() {
    std::vector<std::string> names;
    for (const SolverKind& kind : solverKinds()) names.push_back(kind.name);
    return names;
}

std::vector<SolverKeyInfo> solverKeys(const SolverConfig& config) {
    std::vector<SolverKeyInfo> out;
    const SolverKind* kind = findSolverKind(config.name);
    if (!kind) return out;
    for (const SolverKey& k : kind->keys) {
        SolverKeyInfo info;
        info.name = k.name, info.doc = k.doc;
        info.type = SolverKeyInfo::Type(int(k.type));
        info.range = k.range();
        info.choices = k.choices;
        info.value = k.get(config);
        out.push_back(std::move(info));
    }
    return out;
}

std::string solverHelp() { return printTable(false); }
std::string solverTableMarkdown() { return printTable(true); }

std::unique_ptr<Solver> makeSolver(const SolverConfig& config, std::string* error) {
    const std::string problem = validate(config);
    if (!problem.empty()) {
        if (error) *error = problem;
        return nullptr;
    }
    return findSolverKind(config.name)->make(config);
}

}  // namespace cloth
