#include <sqlite3.h>

#include <cmath>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>

#include "absl/strings/str_cat.h"
#include "storage/diagnosis_rows.h"
#include "storage/migrations.h"
#include "storage/sqlite_util.h"
#include "storage/study_store.h"

namespace gaitforge::storage {
namespace {

constexpr int kBusyTimeoutMs = 10000;

absl::StatusOr<sqlite3*> OpenConnection(const std::string& path, bool create) {
  sqlite3* db = nullptr;
  int flags = SQLITE_OPEN_READWRITE | SQLITE_OPEN_NOMUTEX | (create ? SQLITE_OPEN_CREATE : 0);
  if (sqlite3_open_v2(path.c_str(), &db, flags, nullptr) != SQLITE_OK) {
    absl::Status s = absl::UnavailableError(
        absl::StrCat("cannot open database '", path, "': ", db ? sqlite3_errmsg(db) : "?"));
    sqlite3_close(db);
    return s;
  }
  sqlite3_busy_timeout(db, kBusyTimeoutMs);
  return db;
}

absl::Status ApplyMigrations(sqlite3* db) {
  if (auto s = Exec(db,
                    "CREATE TABLE IF NOT EXISTS schema_migrations (version INTEGER PRIMARY KEY, "
                    "name TEXT NOT NULL, applied_ms INTEGER NOT NULL)");
      !s.ok())
    return s;
  Statement q(db, "SELECT COALESCE(MAX(version), 0) FROM schema_migrations");
  if (!q.Step()) return q.status();
  const int64_t have = q.Int(0);
  const auto& all = Migrations();
  if (have > static_cast<int64_t>(all.size()))
    return absl::FailedPreconditionError(absl::StrCat(
        "database schema version ", have, " is newer than this build's (", all.size(), ")"));
  for (size_t v = have; v < all.size(); ++v) {
    if (auto s = Exec(db, "BEGIN IMMEDIATE"); !s.ok()) return s;
    absl::Status s = Exec(db, all[v].sql);
    if (s.ok()) {
      Statement ins(db,
                    "INSERT INTO schema_migrations(version, name, applied_ms) "
                    "VALUES (?, ?, strftime('%s','now') * 1000)");
      s = ins.Bind(1, static_cast<int64_t>(v + 1)).Bind(2, all[v].name).Run();
    }
    if (!s.ok()) {
      Exec(db, "ROLLBACK").IgnoreError();
      return absl::InternalError(absl::StrCat("migration ", all[v].name, ": ", s.message()));
    }
    if (auto c = Exec(db, "COMMIT"); !c.ok()) return c;
  }
  return absl::OkStatus();
}

RecordingRecord ReadRecording(Statement& q) {
  RecordingRecord r;
  r.hash = q.Text(0);
  r.name = q.Text(1);
  r.robot = q.Text(2);
  r.rows = q.Int(3);
  std::string channels = q.Text(4);
  size_t start = 0;
  while (start <= channels.size() && !channels.empty()) {
    const size_t comma = channels.find(',', start);
    r.channels.push_back(channels.substr(start, comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  r.dt = q.Real(5);
  r.dropped_rows = static_cast<int>(q.Int(6));
  r.csv = q.Blob(7);
  r.sidecar = q.Blob(8);
  r.added_ms = q.Int(9);
  r.bytes = q.Int(10);
  return r;
}

StudyRecord ReadStudy(Statement& q) {
  StudyRecord r;
  r.study_id = q.Text(0);
  r.name = q.Text(1);
  r.spec = q.Blob(2);
  r.spec_json = q.Text(3);
  r.state = q.Text(4);
  r.generations_total = static_cast<int>(q.Int(5));
  r.generations_done = static_cast<int>(q.Int(6));
  r.best_fitness = q.OptReal(7);
  r.mean_fitness = q.OptReal(8);
  r.evaluations = q.Int(9);
  r.created_ms = q.Int(10);
  r.updated_ms = q.Int(11);
  r.error = q.Text(12);
  r.sim_build = q.Text(13);
  return r;
}

constexpr const char* kStudyColumns =
    "study_id, name, spec, spec_json, state, generations_total, generations_done, "
    "best_fitness, mean_fitness, evaluations, created_ms, updated_ms, error, sim_build";

class SqliteStore final : public StudyStore {
 public:
  SqliteStore(std::string path, sqlite3* writer) : path_(std::move(path)), writer_(writer) {
    thread_ = std::thread([this] { WriterLoop(); });
  }

  ~SqliteStore() override {
    {
      std::lock_guard<std::mutex> l(mu_);
      stopping_ = true;
    }
    cv_.notify_all();
    thread_.join();
    sqlite3_close(writer_);
    for (sqlite3* r : readers_) sqlite3_close(r);
  }

  std::future<absl::Status> CreateStudy(const StudyRecord& s) override {
    return Submit([s](sqlite3* db) {
      Statement q(db, absl::StrCat("INSERT INTO studies(", kStudyColumns,
                                   ") VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?)"));
      return q.Bind(1, s.study_id)
          .Bind(2, s.name)
          .BindBlob(3, s.spec)
          .Bind(4, s.spec_json)
          .Bind(5, s.state)
          .Bind(6, s.generations_total)
          .Bind(7, s.generations_done)
          .Bind(8, s.best_fitness)
          .Bind(9, s.mean_fitness)
          .Bind(10, s.evaluations)
          .Bind(11, s.created_ms)
          .Bind(12, s.updated_ms)
          .Bind(13, s.error)
          .Bind(14, s.sim_build)
          .Run();
    });
  }

  std::future<absl::Status> AppendResults(std::vector<IndividualRecord> results) override {
    return Submit([this, results = std::move(results)](sqlite3*) {
      IndividualInserter& ins = Inserter();
      for (const auto& r : results) {
        if (auto s = InsertIndividual(ins, r); !s.ok()) return s;
      }
      return absl::OkStatus();
    });
  }

  std::future<absl::Status> CommitGeneration(GenerationRecord g) override {
    return Submit([this, g = std::move(g)](sqlite3* db) -> absl::Status {
      IndividualInserter& ins = Inserter();
      for (const auto& r : g.carried) {
        if (auto s = InsertIndividual(ins, r); !s.ok()) return s;
      }
      Statement gen(db,
                    "INSERT INTO generations(study_id, generation, best, mean, stddev, diversity, "
                    "evaluations, invalid, committed_ms, engine_state, leases, lease_expiries, "
                    "duplicates, backups, poisoned) VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
      if (auto s = gen.Bind(1, g.study_id)
                       .Bind(2, g.generation)
                       .Bind(3, g.best)
                       .Bind(4, g.mean)
                       .Bind(5, g.stddev)
                       .Bind(6, g.diversity)
                       .Bind(7, g.evaluations)
                       .Bind(8, g.invalid)
                       .Bind(9, g.committed_ms)
                       .BindBlob(10, g.engine_state)
                       .Bind(11, g.counters.leases)
                       .Bind(12, g.counters.lease_expiries)
                       .Bind(13, g.counters.duplicates)
                       .Bind(14, g.counters.backups)
                       .Bind(15, g.counters.poisoned)
                       .Run();
          !s.ok())
        return s;
      Statement hof(db,
                    "INSERT INTO hall_of_fame(study_id, generation, rank, origin_generation, "
                    "origin_member, genes, genes_json, valid, fitness) VALUES (?,?,?,?,?,?,?,?,?)");
      for (const auto& h : g.hall_of_fame) {
        if (auto s = hof.Bind(1, g.study_id)
                         .Bind(2, g.generation)
                         .Bind(3, h.rank)
                         .Bind(4, h.origin_generation)
                         .Bind(5, h.origin_member)
                         .BindBlob(6, EncodeDoubles(h.genes))
                         .Bind(7, DoublesJson(h.genes))
                         .Bind(8, h.valid ? 1 : 0)
                         .Bind(9, h.valid ? std::optional<double>(h.fitness) : std::nullopt)
                         .Run();
            !s.ok())
          return s;
      }
      Statement study(db,
                      "UPDATE studies SET generations_done = ?, best_fitness = ?, "
                      "mean_fitness = ?, evaluations = ?, state = ?, updated_ms = ? "
                      "WHERE study_id = ?");
      return study.Bind(1, g.generation + 1)
          .Bind(2, g.study_best)
          .Bind(3, g.mean)
          .Bind(4, g.study_evaluations)
          .Bind(5, g.study_state)
          .Bind(6, g.committed_ms)
          .Bind(7, g.study_id)
          .Run();
    });
  }

  std::future<absl::Status> SetStudySimBuild(const std::string& id,
                                             const std::string& build) override {
    return Submit([id, build](sqlite3* db) -> absl::Status {
      Statement q(db, "UPDATE studies SET sim_build = ? WHERE study_id = ?");
      return q.Bind(1, build).Bind(2, id).Run();
    });
  }

  std::future<absl::Status> SetStudyState(const std::string& id, const std::string& state,
                                          const std::string& error) override {
    return Submit([id, state, error](sqlite3* db) -> absl::Status {
      Statement q(db,
                  "UPDATE studies SET state = ?, error = ?, "
                  "updated_ms = CAST((julianday('now') - 2440587.5) * 86400000 AS INTEGER) "
                  "WHERE study_id = ?");
      if (auto s = q.Bind(1, state).Bind(2, error).Bind(3, id).Run(); !s.ok()) return s;
      if (sqlite3_changes(db) == 0) return absl::NotFoundError(absl::StrCat("study ", id));
      return absl::OkStatus();
    });
  }

  std::future<absl::StatusOr<bool>> PutRecording(const RecordingRecord& r) override {
    auto inserted = std::make_shared<bool>(false);  // written by the writer thread's op
    auto done = Submit([r, inserted](sqlite3* db) -> absl::Status {
      Statement q(db,
                  "INSERT OR IGNORE INTO recordings(hash, name, robot, rows, channels, dt, "
                  "dropped_rows, csv, sidecar, added_ms) VALUES (?,?,?,?,?,?,?,?,?,?)");
      std::string channels;
      for (const auto& c : r.channels) channels += (channels.empty() ? "" : ",") + c;
      absl::Status s = q.Bind(1, r.hash)
                           .Bind(2, r.name)
                           .Bind(3, r.robot)
                           .Bind(4, r.rows)
                           .Bind(5, channels)
                           .Bind(6, r.dt)
                           .Bind(7, r.dropped_rows)
                           .BindBlob(8, r.csv)
                           .BindBlob(9, r.sidecar)
                           .Bind(10, r.added_ms)
                           .Run();
      *inserted = s.ok() && sqlite3_changes(db) > 0;
      return s;
    });
    // Resolved in the caller's thread once the transaction has committed (or failed).
    return std::async(std::launch::deferred,
                      [done = std::move(done), inserted]() mutable -> absl::StatusOr<bool> {
                        absl::Status s = done.get();
                        if (!s.ok()) return s;
                        return *inserted;
                      });
  }

  std::future<absl::Status> PutDiagnosis(const DiagnosisRecord& d) override {
    return Submit([d](sqlite3* db) { return WriteDiagnosis(db, d); });
  }

  absl::StatusOr<DiagnosisRecord> GetDiagnosis(const std::string& id, bool with_files) override {
    return WithReader([&](sqlite3* db) { return ReadDiagnosis(db, id, with_files); });
  }

  absl::StatusOr<std::vector<DiagnosisRecord>> ListDiagnoses() override {
    return WithReader([&](sqlite3* db) { return ReadDiagnoses(db); });
  }

  absl::StatusOr<RecordingRecord> GetRecording(const std::string& hash, bool with_bytes) override {
    return WithReader([&](sqlite3* db) -> absl::StatusOr<RecordingRecord> {
      Statement q(db, absl::StrCat("SELECT hash, name, robot, rows, channels, dt, dropped_rows, ",
                                   with_bytes ? "csv, sidecar" : "'', ''",
                                   ", added_ms, length(csv) + length(sidecar) "
                                   "FROM recordings WHERE hash = ?"));
      q.Bind(1, hash);
      if (q.Step()) return ReadRecording(q);
      if (!q.status().ok()) return q.status();
      return absl::NotFoundError(absl::StrCat("no recording with hash '", hash, "'"));
    });
  }

  absl::StatusOr<std::vector<RecordingRecord>> ListRecordings() override {
    return WithReader([&](sqlite3* db) -> absl::StatusOr<std::vector<RecordingRecord>> {
      Statement q(db,
                  "SELECT hash, name, robot, rows, channels, dt, dropped_rows, '', '', added_ms, "
                  "length(csv) + length(sidecar) FROM recordings ORDER BY added_ms, hash");
      std::vector<RecordingRecord> out;
      while (q.Step()) out.push_back(ReadRecording(q));
      if (!q.status().ok()) return q.status();
      return out;
    });
  }

  void SetCommitObserver(std::function<void(double)> observer) override {
    std::lock_guard<std::mutex> l(mu_);
    observer_ = std::move(observer);
  }

  absl::Status Flush() override {
    return Submit([](sqlite3*) { return absl::OkStatus(); }).get();
  }

  absl::StatusOr<StudyRecord> GetStudy(const std::string& id) override {
    return WithReader([&](sqlite3* db) -> absl::StatusOr<StudyRecord> {
      Statement q(db, absl::StrCat("SELECT ", kStudyColumns, " FROM studies WHERE study_id = ?"));
      q.Bind(1, id);
      if (q.Step()) return ReadStudy(q);
      if (!q.status().ok()) return q.status();
      return absl::NotFoundError(absl::StrCat("no study with id '", id, "'"));
    });
  }

  absl::StatusOr<std::vector<StudyRecord>> ListStudies() override {
    return WithReader([&](sqlite3* db) -> absl::StatusOr<std::vector<StudyRecord>> {
      Statement q(db, absl::StrCat("SELECT ", kStudyColumns,
                                   " FROM studies ORDER BY created_ms, study_id"));
      std::vector<StudyRecord> out;
      while (q.Step()) out.push_back(ReadStudy(q));
      if (!q.status().ok()) return q.status();
      return out;
    });
  }

  absl::StatusOr<std::vector<GenerationRecord>> History(const std::string& id) override {
    if (auto s = GetStudy(id); !s.ok()) return s.status();
    return WithReader([&](sqlite3* db) -> absl::StatusOr<std::vector<GenerationRecord>> {
      Statement q(db,
                  "SELECT generation, best, mean, stddev, diversity, evaluations, invalid, "
                  "committed_ms, leases, lease_expiries, duplicates, backups, poisoned, "
                  // The commonest reason of the generation's invalid members (the first
                  // in byte order among equals), from the members' own rows.
                  "(SELECT reason FROM individuals i WHERE i.study_id = g.study_id AND "
                  "i.generation = g.generation AND i.valid = 0 GROUP BY reason "
                  "ORDER BY COUNT(*) DESC, reason LIMIT 1) "
                  "FROM generations g WHERE study_id = ? ORDER BY generation");
      q.Bind(1, id);
      std::vector<GenerationRecord> out;
      while (q.Step()) {
        GenerationRecord g;
        g.study_id = id;
        g.generation = static_cast<int>(q.Int(0));
        // NULL (an all-invalid generation's NaN) reads back as NaN, not 0.
        g.best = q.OptReal(1).value_or(NAN);
        g.mean = q.OptReal(2).value_or(NAN);
        g.stddev = q.OptReal(3).value_or(NAN);
        g.diversity = q.OptReal(4).value_or(NAN);
        g.evaluations = static_cast<int>(q.Int(5));
        g.invalid = static_cast<int>(q.Int(6));
        g.committed_ms = q.Int(7);
        g.counters = JobCounters{q.Int(8), q.Int(9), q.Int(10), q.Int(11), q.Int(12)};
        g.invalid_reason = q.Text(13);
        out.push_back(std::move(g));
      }
      if (!q.status().ok()) return q.status();
      return out;
    });
  }

  absl::StatusOr<std::pair<int, std::vector<HofRecord>>> HallOfFame(
      const std::string& id, std::optional<int> generation) override {
    auto study = GetStudy(id);
    if (!study.ok()) return study.status();
    int g;
    if (generation) {
      if (*generation < 0 || *generation >= study->generations_done)
        return absl::OutOfRangeError(absl::StrCat(
            "generation = ", *generation, " is out of range: study '", id, "' has committed ",
            study->generations_done == 0
                ? std::string("no generation yet")
                : absl::StrCat("generations [0, ", study->generations_done - 1, "]")));
      g = *generation;
    } else {
      if (study->generations_done == 0)
        return absl::FailedPreconditionError(
            absl::StrCat("study '", id, "' has not committed a generation yet"));
      g = study->generations_done - 1;
    }
    return WithReader([&](sqlite3* db) -> absl::StatusOr<std::pair<int, std::vector<HofRecord>>> {
      Statement q(db,
                  "SELECT rank, origin_generation, origin_member, genes, valid, fitness "
                  "FROM hall_of_fame WHERE study_id = ? AND generation = ? ORDER BY rank");
      q.Bind(1, id).Bind(2, g);
      std::vector<HofRecord> out;
      while (q.Step()) {
        HofRecord h;
        h.rank = static_cast<int>(q.Int(0));
        h.origin_generation = static_cast<int>(q.Int(1));
        h.origin_member = static_cast<int>(q.Int(2));
        h.genes = DecodeDoubles(q.Blob(3));
        h.valid = q.Int(4) != 0;
        h.fitness = q.Real(5);
        out.push_back(std::move(h));
      }
      if (!q.status().ok()) return q.status();
      return std::make_pair(g, std::move(out));
    });
  }

  absl::StatusOr<std::vector<IndividualRecord>> Individuals(const std::string& id,
                                                            int generation) override {
    if (auto s = GetStudy(id); !s.ok()) return s.status();
    return WithReader([&](sqlite3* db) -> absl::StatusOr<std::vector<IndividualRecord>> {
      Statement q(db,
                  "SELECT member, genes, valid, fitness, reason, worker_id, eval_seconds, "
                  "carried, origin_generation, origin_member, reported_ms, violation "
                  "FROM individuals "
                  "WHERE study_id = ? AND generation = ? ORDER BY member");
      q.Bind(1, id).Bind(2, generation);
      std::vector<IndividualRecord> out;
      while (q.Step()) {
        IndividualRecord r;
        r.study_id = id;
        r.generation = generation;
        r.member = static_cast<int>(q.Int(0));
        r.genes = DecodeDoubles(q.Blob(1));
        r.valid = q.Int(2) != 0;
        r.fitness = q.Real(3);
        r.reason = q.Text(4);
        r.worker_id = q.Text(5);
        r.eval_seconds = q.Real(6);
        r.carried = q.Int(7) != 0;
        r.origin_generation = static_cast<int>(q.Int(8));
        r.origin_member = static_cast<int>(q.Int(9));
        r.reported_ms = q.Int(10);
        r.violation = q.Real(11);
        out.push_back(std::move(r));
      }
      if (!q.status().ok()) return q.status();
      Statement m(db,
                  "SELECT member, name, value FROM metrics WHERE study_id = ? AND generation = ? "
                  "ORDER BY member, name");
      m.Bind(1, id).Bind(2, generation);
      size_t i = 0;
      while (m.Step()) {
        const int member = static_cast<int>(m.Int(0));
        while (i < out.size() && out[i].member < member) ++i;
        if (i < out.size() && out[i].member == member) out[i].metrics[m.Text(1)] = m.Real(2);
      }
      if (!m.status().ok()) return m.status();
      return out;
    });
  }

  absl::StatusOr<std::optional<std::pair<int, std::string>>> LatestEngineState(
      const std::string& id) override {
    return WithReader(
        [&](sqlite3* db) -> absl::StatusOr<std::optional<std::pair<int, std::string>>> {
          Statement q(db,
                      "SELECT generation, engine_state FROM generations WHERE study_id = ? "
                      "ORDER BY generation DESC LIMIT 1");
          q.Bind(1, id);
          if (q.Step())
            return std::make_optional(std::make_pair(static_cast<int>(q.Int(0)), q.Blob(1)));
          if (!q.status().ok()) return q.status();
          return std::optional<std::pair<int, std::string>>();
        });
  }

 private:
  using Op = std::function<absl::Status(sqlite3*)>;
  struct Pending {
    Op op;
    std::promise<absl::Status> done;
  };

  // Prepared once per write op and reused for every row of it.
  struct IndividualInserter {
    explicit IndividualInserter(sqlite3* db)
        : q(db,
            "INSERT OR IGNORE INTO individuals(study_id, generation, member, genes, "
            "genes_json, valid, fitness, reason, worker_id, eval_seconds, carried, "
            "origin_generation, origin_member, reported_ms, violation) VALUES "
            "(?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)"),
          m(db,
            "INSERT OR IGNORE INTO metrics(study_id, generation, member, name, value) "
            "VALUES (?,?,?,?,?)") {}
    Statement q;
    Statement m;
  };

  // The writer's INSERTs of results, prepared once (issue 30: preparing them for every
  // Report was ~4% of the coordinator's CPU at 1,024 workers). Writer thread only.
  IndividualInserter& Inserter() {
    if (!inserter_) inserter_ = std::make_unique<IndividualInserter>(writer_);
    return *inserter_;
  }
  std::unique_ptr<IndividualInserter> inserter_;

  static absl::Status InsertIndividual(IndividualInserter& ins, const IndividualRecord& r) {
    Statement& q = ins.q;
    Statement& m = ins.m;
    if (auto s = q.Bind(1, r.study_id)
                     .Bind(2, r.generation)
                     .Bind(3, r.member)
                     .BindBlob(4, EncodeDoubles(r.genes))
                     .Bind(5, DoublesJson(r.genes))
                     .Bind(6, r.valid ? 1 : 0)
                     .Bind(7, r.valid ? std::optional<double>(r.fitness) : std::nullopt)
                     .Bind(8, r.reason)
                     .Bind(9, r.worker_id)
                     .Bind(10, r.eval_seconds)
                     .Bind(11, r.carried ? 1 : 0)
                     .Bind(12, r.origin_generation)
                     .Bind(13, r.origin_member)
                     .Bind(14, r.reported_ms)
                     .Bind(15, r.violation)
                     .Run();
        !s.ok())
      return s;
    for (const auto& [name, value] : r.metrics) {
      if (auto s = m.Bind(1, r.study_id)
                       .Bind(2, r.generation)
                       .Bind(3, r.member)
                       .Bind(4, name)
                       .Bind(5, value)
                       .Run();
          !s.ok())
        return s;
    }
    return absl::OkStatus();
  }

  std::future<absl::Status> Submit(Op op) {
    Pending p{std::move(op), {}};
    auto f = p.done.get_future();
    {
      std::lock_guard<std::mutex> l(mu_);
      queue_.push_back(std::move(p));
    }
    cv_.notify_one();
    return f;
  }

  // Drains the queue: every op runs inside a savepoint of one transaction, so a failing
  // op leaves nothing behind while the others still commit together (group commit).
  void WriterLoop() {
    for (;;) {
      std::deque<Pending> batch;
      std::function<void(double)> observer;
      {
        std::unique_lock<std::mutex> l(mu_);
        cv_.wait(l, [&] { return stopping_ || !queue_.empty(); });
        if (queue_.empty() && stopping_) {
          inserter_.reset();  // finalized here, before the destructor closes the connection
          return;
        }
        batch.swap(queue_);
        observer = observer_;
      }
      const auto started = std::chrono::steady_clock::now();
      std::vector<absl::Status> results;
      absl::Status begin = Exec(writer_, "BEGIN IMMEDIATE");
      for (auto& p : batch) {
        if (!begin.ok()) {
          results.push_back(begin);
          continue;
        }
        Exec(writer_, "SAVEPOINT op").IgnoreError();
        absl::Status s = p.op(writer_);
        if (s.ok()) {
          Exec(writer_, "RELEASE op").IgnoreError();
        } else {
          Exec(writer_, "ROLLBACK TO op").IgnoreError();
          Exec(writer_, "RELEASE op").IgnoreError();
        }
        results.push_back(s);
      }
      if (begin.ok()) {
        absl::Status c = Exec(writer_, "COMMIT");
        if (!c.ok()) {
          Exec(writer_, "ROLLBACK").IgnoreError();
          for (auto& r : results) {
            if (r.ok()) r = c;
          }
        }
      }
      if (observer)
        observer(std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
      for (size_t i = 0; i < batch.size(); ++i) batch[i].done.set_value(results[i]);
    }
  }

  template <typename F>
  auto WithReader(F&& f) -> decltype(f(nullptr)) {
    sqlite3* db = nullptr;
    {
      std::lock_guard<std::mutex> l(readers_mu_);
      if (!free_readers_.empty()) {
        db = free_readers_.back();
        free_readers_.pop_back();
      }
    }
    if (!db) {
      auto opened = OpenConnection(path_, false);
      if (!opened.ok()) return opened.status();
      db = *opened;
      std::lock_guard<std::mutex> l(readers_mu_);
      readers_.push_back(db);
    }
    auto result = f(db);
    std::lock_guard<std::mutex> l(readers_mu_);
    free_readers_.push_back(db);
    return result;
  }

  const std::string path_;
  sqlite3* const writer_;
  std::mutex mu_;
  std::condition_variable cv_;
  std::deque<Pending> queue_;  // guarded by mu_
  bool stopping_ = false;      // guarded by mu_
  std::function<void(double)> observer_;  // guarded by mu_
  std::thread thread_;
  std::mutex readers_mu_;
  std::vector<sqlite3*> readers_;       // guarded by readers_mu_ (all, for closing)
  std::vector<sqlite3*> free_readers_;  // guarded by readers_mu_
};

}  // namespace

absl::StatusOr<std::unique_ptr<StudyStore>> OpenSqliteStore(const std::string& path,
                                                            Durability durability) {
  auto db = OpenConnection(path, true);
  if (!db.ok()) return db.status();
  for (const char* pragma : {"PRAGMA journal_mode=WAL", "PRAGMA foreign_keys=ON",
                             "PRAGMA journal_size_limit=67108864"}) {
    if (auto s = Exec(*db, pragma); !s.ok()) {
      sqlite3_close(*db);
      return s;
    }
  }
  if (auto s = Exec(*db, durability.full_sync ? "PRAGMA synchronous=FULL"
                                              : "PRAGMA synchronous=NORMAL");
      !s.ok()) {
    sqlite3_close(*db);
    return s;
  }
  if (auto s = ApplyMigrations(*db); !s.ok()) {
    sqlite3_close(*db);
    return s;
  }
  return std::unique_ptr<StudyStore>(new SqliteStore(path, *db));
}

}  // namespace gaitforge::storage
