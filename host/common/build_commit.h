/* build_commit.h — the commit a binary was built from, for provenance in
 * summary.json and the snapshots (generated at every build by
 * cmake/build_commit.cmake; "" outside a git checkout). */
#ifndef SPH_BUILD_COMMIT_H
#define SPH_BUILD_COMMIT_H

const char *sph_build_commit(void);

#endif
