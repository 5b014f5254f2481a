# The OpenCL driver search of the GPU kit's run.sh (sourced, not run). The kit brings its own ICD loader
# (ocl-icd's libOpenCL.so.1, beside the binaries); what it needs from the machine is the vendor's
# driver library. driver_search finds it, whether or not the image registers it, and points the loader
# at it alone: it writes WORK/vendors/<vendor>.icd holding the library's absolute path and exports
# OCL_ICD_VENDORS=WORK/vendors (empty when nothing was found, so that the loader then sees no platform
# rather than whatever else the machine registers), and appends the library's folder to
# LD_LIBRARY_PATH (the driver loads its own companions, libcuda.so.1 and the like, from there), after
# the kit's bin/ (fit_glibc puts that first).
#
# Everything it looked at and everything it saw goes to the log and into DRIVER_JSON.
# PDMESH_KIT_SEARCH_ROOT=DIR makes every system path of the search relative to DIR (and leaves out
# the loader cache and LD_LIBRARY_PATH): the deliberately broken search, with DIR empty, is how the
# kit's test shows that a machine without a driver is reported rather than failed on.

# The folders searched for the driver library, under the search root.
driver_lib_dirs() {
  local r=$1
  printf '%s\n' "$r/usr/local/nvidia/lib64" "$r/usr/local/nvidia/lib" "$r/usr/lib/x86_64-linux-gnu" \
    "$r/usr/lib64" "$r/usr/lib" "$r/lib/x86_64-linux-gnu" "$r/lib64" "$r/usr/local/cuda/lib64" \
    "$r/usr/local/cuda/compat" "$r/usr/local/lib"
}

# The folders searched for ICD registrations (*.icd), under the search root.
driver_icd_dirs() {
  local r=$1
  printf '%s\n' "$r/etc/OpenCL/vendors" "$r/usr/local/nvidia/etc/OpenCL/vendors" "$r/usr/local/etc/OpenCL/vendors" \
    "$r/usr/share/nvidia" "$r/usr/local/nvidia/share/nvidia"
}

# driver_search MODE WORK LOG: MODE gpu looks for NVIDIA's libnvidia-opencl.so*, local for PoCL's
# libpocl.so*. Sets DRIVER_LIB (the chosen library, or empty) and DRIVER_JSON (an object).
driver_search() {
  local mode=$1 work=$2 log=$3 root=${PDMESH_KIT_SEARCH_ROOT:-}
  local pattern vendor
  if [ "$mode" = local ]; then pattern='libpocl.so*' vendor=pocl; else pattern='libnvidia-opencl.so*' vendor=nvidia; fi
  local -a lib_dirs=() icd_dirs=() libs=() icds=() icd_facts=() system_loaders=() ld_path_dirs=()
  mapfile -t lib_dirs < <(driver_lib_dirs "$root")
  mapfile -t icd_dirs < <(driver_icd_dirs "$root")
  local caller_vendors=${OCL_ICD_VENDORS-}
  DRIVER_VENDORS_GIVEN=$caller_vendors
  [ -n "$caller_vendors" ] && icd_dirs+=("$caller_vendors")
  if [ -z "$root" ] && [ -n "${LD_LIBRARY_PATH:-}" ]; then
    IFS=: read -r -a ld_path_dirs <<<"$LD_LIBRARY_PATH"
    lib_dirs+=("${ld_path_dirs[@]}")
  fi
  {
    echo "== driver search (mode $mode; search root '${root:-/}')"
    echo "looking for $pattern in: ${lib_dirs[*]}"
    echo "looking for *.icd in: ${icd_dirs[*]}"
    echo "OCL_ICD_VENDORS as given: '${caller_vendors}'"
  } >>"$log"

  local d f
  for d in "${lib_dirs[@]}"; do
    [ -d "$d" ] || continue
    while IFS= read -r f; do libs+=("$f"); done < <(find "$d" -maxdepth 3 -name "$pattern" \( -type f -o -type l \) 2>/dev/null | sort)
    while IFS= read -r f; do system_loaders+=("$f"); done < <(find "$d" -maxdepth 1 -name 'libOpenCL.so*' 2>/dev/null | sort)
  done
  if [ -z "$root" ]; then
    local cache
    cache=$( { ldconfig -p 2>/dev/null || /sbin/ldconfig -p 2>/dev/null; } | awk -v p="${pattern%\*}" 'index($1, p) == 1 { print $NF }')
    while IFS= read -r f; do [ -n "$f" ] && libs+=("$f"); done <<<"$cache"
  fi
  # Unique, in the order found (/lib and /usr/lib are often one folder).
  local -A seen=()
  local -a unique=()
  local key
  for f in "${libs[@]}"; do
    key=$(readlink -f "$(dirname "$f")")/$(basename "$f")
    [ -n "${seen[$key]:-}" ] || { seen[$key]=1; unique+=("$f"); }
  done
  libs=("${unique[@]}")

  # Registrations: which library each .icd names, and whether that library is there.
  local registered=
  for d in "${icd_dirs[@]}"; do
    [ -d "$d" ] || continue
    for f in "$d"/*.icd; do
      [ -f "$f" ] || continue
      icds+=("$f")
      local named resolved=
      named=$(head -n 1 "$f" | tr -d '[:space:]')
      if [[ $named == /* ]]; then
        [ -e "$named" ] && resolved=$named
      else
        local l
        for l in "${libs[@]}"; do [ "$(basename "$l")" = "$named" ] && { resolved=$l; break; }; done
      fi
      if [ -n "$resolved" ]; then icd_facts+=("$f names '$named' -> $resolved"); else icd_facts+=("$f names '$named' (not found)"); fi
      if [ -n "$resolved" ] && [ -z "$registered" ] && [[ $(basename "$resolved") == ${pattern} ]]; then
        registered=$resolved
      fi
    done
  done

  # The library to use: the registered one, else the found one with the shortest name
  # (libnvidia-opencl.so.1 before libnvidia-opencl.so.580.159.03; the same file).
  DRIVER_LIB=$registered
  if [ -z "$DRIVER_LIB" ]; then
    for f in "${libs[@]}"; do
      [ -e "$f" ] || continue
      if [ -z "$DRIVER_LIB" ] || [ ${#f} -lt ${#DRIVER_LIB} ]; then DRIVER_LIB=$f; fi
    done
  fi

  mkdir -p "$work/vendors"
  rm -f "$work/vendors"/*.icd
  export OCL_ICD_VENDORS=$work/vendors
  local how
  if [ -n "$DRIVER_LIB" ]; then
    echo "$DRIVER_LIB" >"$work/vendors/$vendor.icd"
    export LD_LIBRARY_PATH=${LD_LIBRARY_PATH:+$LD_LIBRARY_PATH:}$(dirname "$DRIVER_LIB")
    if [ -n "$registered" ]; then how="registered by the image (${icds[*]})"; else how="not registered by the image: the kit registered it"; fi
  else
    how="none found"
  fi
  {
    echo "libraries found: ${libs[*]:-none}"
    echo "ICD files found: ${icds[*]:-none}"
    local fact
    for fact in "${icd_facts[@]}"; do echo "  $fact"; done
    echo "system ICD loaders (libOpenCL.so*) found: ${system_loaders[*]:-none} (the kit uses its own)"
    echo "chosen: ${DRIVER_LIB:-none} ($how)"
    echo "OCL_ICD_VENDORS=$OCL_ICD_VENDORS ($(ls "$OCL_ICD_VENDORS" | tr '\n' ' '))"
    echo "LD_LIBRARY_PATH=${LD_LIBRARY_PATH:-}"
  } >>"$log"

  DRIVER_JSON=$(printf '{"looked_for": %s, "search_root": %s, "library_folders": %s, "icd_folders": %s, "ocl_icd_vendors_given": %s, "libraries_found": %s, "icd_files": %s, "system_icd_loaders": %s, "chosen": %s, "how": %s, "ocl_icd_vendors_used": %s}' \
    "$(json_str "$pattern")" "$(json_str "${root:-/}")" "$(json_str_array "${lib_dirs[@]}")" \
    "$(json_str_array "${icd_dirs[@]}")" "$(json_str "$caller_vendors")" "$(json_str_array "${libs[@]}")" \
    "$(json_str_array "${icd_facts[@]}")" "$(json_str_array "${system_loaders[@]}")" \
    "$( [ -n "$DRIVER_LIB" ] && json_str "$DRIVER_LIB" || printf null)" "$(json_str "$how")" \
    "$(json_str "$OCL_ICD_VENDORS")")
}

# nvidia-smi's facts: sets SMI_JSON (an object, or null where nvidia-smi is not there) and appends
# its whole output to the log.
nvidia_smi_facts() {
  local log=$1 root=${PDMESH_KIT_SEARCH_ROOT:-} smi= c
  for c in "$root/usr/bin/nvidia-smi" "$root/usr/local/nvidia/bin/nvidia-smi" "$root/usr/local/bin/nvidia-smi"; do
    [ -x "$c" ] && { smi=$c; break; }
  done
  [ -z "$smi" ] && [ -z "$root" ] && smi=$(command -v nvidia-smi 2>/dev/null || true)
  if [ -z "$smi" ]; then
    local where="$root/usr/bin, $root/usr/local/nvidia/bin, $root/usr/local/bin"
    [ -n "$root" ] || where="$where, PATH"
    echo "== nvidia-smi: not found (looked in $where)" >>"$log"
    SMI_JSON=null
    return
  fi
  echo "== $smi" >>"$log"
  timeout -k 2 20 "$smi" >>"$log" 2>&1 || echo "(nvidia-smi failed: status $?)" >>"$log"
  local query
  query=$(timeout -k 2 20 "$smi" --query-gpu=name,driver_version,memory.total,clocks.max.sm,clocks.max.mem,compute_cap,pci.bus_id \
    --format=csv,noheader 2>&1 | head -n 1)
  echo "query: $query" >>"$log"
  local -a q
  IFS=, read -r -a q <<<"$query"
  SMI_JSON=$(printf '{"path": %s, "query": %s, "name": %s, "driver_version": %s, "memory_total": %s, "max_sm_clock": %s, "max_memory_clock": %s, "compute_capability": %s}' \
    "$(json_str "$smi")" "$(json_str "$query")" "$(json_str "${q[0]:-}")" "$(json_str "${q[1]# }")" \
    "$(json_str "${q[2]# }")" "$(json_str "${q[3]# }")" "$(json_str "${q[4]# }")" "$(json_str "${q[5]# }")")
}
