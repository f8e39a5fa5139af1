#pragma once
#include <string>
#include <vector>

namespace gaitforge::storage {

// One schema step. Version i + 1 is Migrations()[i]; applied ones are recorded in
// schema_migrations, so opening a database brings it up to date exactly once.
struct Migration {
  std::string name;
  std::string sql;
};

const std::vector<Migration>& Migrations();

}  // namespace gaitforge::storage
