#pragma once
// Deleting an account and everything of theirs: the one path behind DELETE /api/v1/users/{name}
// (a running server) and `cathbox-server admin delete-user NAME` (a stopped one).
//  1. Store::delete_user: the account, its results with their records and metrics, the
//     assignments made for it, its tokens, live rigs and login failures, in one transaction;
//  2. what the server derived from those records: their traces in the cache (memory and disk);
//  3. its live streams on this instance (ended now, watchers told), when a LiveService is given;
//  4. Database::scrub: the database's own leftover copies of the deleted bytes;
//  5. one audit row (user.delete, detail results=N), written after the delete succeeded.
#include <cstdint>
#include <string>

#include "server/artifact_cache.hpp"
#include "server/audit_log.hpp"
#include "server/live_service.hpp"
#include "server/result.hpp"
#include "server/store.hpp"

namespace cathbox::server {

struct UserDeletion {
  int results = 0;       // results (with their records) deleted
  int live_streams = 0;  // live streams ended on this instance
};

// `who`: the audit row's actor, time and address (its action, target and detail are filled in).
// 404 when there is no such user, 409 when it is the last enabled admin; nothing changes then.
// `cache` and `live` may be null (the command line has no live streams).
[[nodiscard]] Result<UserDeletion> delete_user_data(Store& store, ArtifactCache* cache, LiveService* live, const std::string& name,
                                                    AuditEntry who);

}  // namespace cathbox::server
