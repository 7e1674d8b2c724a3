# Shared by the package checks (sourced): make packages with CPack, run lintian on one.
# make_packages BUILD_DIR OUT_DIR COMPONENT...: CPack makes the packages of those components
# (CPACK_COMPONENTS_ALL) into OUT_DIR, a fresh folder.
make_packages() {
  local build=$1 out=$2
  shift 2
  rm -rf "$out"
  mkdir -p "$out"
  local components
  components=$(IFS=';'; echo "$*")
  cpack --config "$build/CPackConfig.cmake" -B "$out" -D "CPACK_COMPONENTS_ALL=$components" >"$out/cpack.log" 2>&1 ||
    { tail -n 5 "$out/cpack.log"; echo "FAIL: cpack ($components)"; exit 1; }
}

# lintian_clean DEB: lintian's warnings are printed; an error fails the check.
lintian_clean() {
  local deb=$1 log status=0
  log="$(dirname "$deb")/lintian-$(basename "$deb" .deb).log"
  lintian --fail-on error --tag-display-limit 0 "$deb" >"$log" 2>&1 || status=$?
  grep -v 'root privileges' "$log" || true
  [ "$status" -eq 0 ] || { echo "FAIL: lintian reports errors in $(basename "$deb") (exit $status)"; exit 1; }
}
