#!/usr/bin/env bash
# Register use of every simulation kernel on GPU targets, without a GPU: compiles the exact program the
# host builds (build/kernel_source prints it: the program builder's defines, common.cl and the kernel
# files in StepProgram's order) in double and float, with each force loop (vector, scalar), for
#   AMD gfx90a (MI200) and gfx1030 (RDNA2): clang-14 + libclc-14 (amdgcn--amdhsa.bc), LLVM's AMDGPU
#     backend, which reports VGPRs, SGPRs, scratch (spills and stack) and occupancy in waves per SIMD;
#   NVIDIA sm_80 (A100): clang-14 + libclc-14 (nvptx64--nvidiacl.bc) to PTX, every function inlined
#     (as NVIDIA's compiler does; LLVM's NVPTX backend would otherwise leave libclc calls), then ptxas
#     -v for registers, stack frame and spill bytes. Warps per SM are estimated from the registers
#     (65536 per SM, 256-register allocation per warp, 64 warps at most, groups of WG_SIZE = 64 work-items).
# Prints one Markdown table (docs/opencl.md, "Force loop"). Needs clang-14, llvm-link-14, opt-14, llc-14,
# libclc-14 (Debian: clang-14 llvm-14 libclc-14 libclc-14-dev) and, for the NVIDIA column, ptxas (CUDA
# toolkit; PATH or /usr/local/cuda/bin); without ptxas that column says so.
#   tools/check/kernel_registers.sh [BUILD_DIR]     (default: build; needs its kernel_source target)
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
source_tool=$build/kernel_source
if [ ! -x "$source_tool" ]; then
  echo "kernel_registers: $source_tool is missing: cmake --build $build --target kernel_source" >&2
  exit 1
fi
for tool in clang-14 llvm-link-14 opt-14 llc-14; do
  command -v "$tool" >/dev/null || { echo "kernel_registers: $tool is not installed" >&2; exit 1; }
done
clc=/usr/lib/clc
for lib in amdgcn--amdhsa.bc nvptx64--nvidiacl.bc; do
  [ -f "$clc/$lib" ] || { echo "kernel_registers: $clc/$lib is missing (libclc-14)" >&2; exit 1; }
done
ptxas=$(command -v ptxas || true)
[ -n "$ptxas" ] || [ ! -x /usr/local/cuda/bin/ptxas ] || ptxas=/usr/local/cuda/bin/ptxas

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cl_flags=(-x cl -cl-std=CL1.2 -nogpulib -O3 -include clc/clc.h -emit-llvm -c)

# AMD: "kernel vgpr sgpr scratch occupancy" per kernel, from the "; Kernel info:" block after each kernel.
amd() {
  local gpu=$1
  clang-14 "${cl_flags[@]}" -target amdgcn--amdhsa -mcpu="$gpu" "$tmp/k.cl" -o "$tmp/a.bc"
  llvm-link-14 --only-needed "$tmp/a.bc" "$clc/amdgcn--amdhsa.bc" -o "$tmp/al.bc"
  llc-14 -O3 -mtriple=amdgcn--amdhsa -mcpu="$gpu" "$tmp/al.bc" -o "$tmp/a.s"
  awk '/^\t\.size\t/ { name = $2; sub(/,$/, "", name) }
       /; Kernel info:/ { cur = name; v = ""; total = "" }
       cur != "" && /; NumSgprs:/ { s = $3 }
       cur != "" && /; NumVgprs:/ { v = $3 }
       cur != "" && /; TotalNumVgprs:/ { total = $3 }  # gfx90a: VGPRs + AGPRs
       cur != "" && /; ScratchSize:/ { sc = $3 }
       cur != "" && /; Occupancy:/ { print cur, (total != "" ? total : v), s, sc, $3; cur = "" }' "$tmp/a.s" >"$tmp/$gpu.txt"
}

# NVIDIA: "kernel registers stack spill_stores spill_loads warps" per kernel, from ptxas -v.
nvidia() {
  clang-14 "${cl_flags[@]}" -target nvptx64--nvidiacl -Xclang -target-cpu -Xclang sm_80 "$tmp/k.cl" -o "$tmp/n.bc"
  llvm-link-14 --only-needed "$tmp/n.bc" "$clc/nvptx64--nvidiacl.bc" -o "$tmp/nl.bc"
  opt-14 -internalize -internalize-public-api-list="$kernels" -inline-threshold=100000 -O3 "$tmp/nl.bc" -o "$tmp/no.bc"
  llc-14 -O3 -mtriple=nvptx64--nvidiacl -mcpu=sm_80 -mattr=+ptx70 "$tmp/no.bc" -o "$tmp/n.ptx"
  if [ -z "$ptxas" ]; then
    : >"$tmp/sm_80.txt"
    return
  fi
  "$ptxas" -arch=sm_80 -v "$tmp/n.ptx" -o "$tmp/n.cubin" 2>"$tmp/ptxas.log"
  awk -F"'" '/Compiling entry function/ { cur = $2; next }
       cur != "" && /bytes stack frame/ { split($0, f, " "); stack = f[1]; st = f[5]; ld = f[9] }
       cur != "" && /Used [0-9]+ registers/ {
         match($0, /Used [0-9]+ registers/); regs = substr($0, RSTART + 5, RLENGTH - 15) + 0
         per_warp = int((regs * 32 + 255) / 256) * 256
         groups = int(int(65536 / per_warp) / 2); if (groups > 32) groups = 32
         warps = groups * 2; if (warps > 64) warps = 64
         print cur, regs, stack, st, ld, warps; cur = "" }' "$tmp/ptxas.log" >"$tmp/sm_80.txt"
}

field() {  # field FILE KERNEL COUNT: the kernel's COUNT values, or COUNT dashes
  awk -v k="$2" -v n="$3" '$1 == k { $1 = ""; sub(/^ /, ""); print; found = 1 }
    END { if (!found) { for (i = 1; i <= n; ++i) printf "- "; print "" } }' "$1"
}

echo "| kernel | precision | force loop | gfx90a: VGPR / SGPR / scratch B / waves per SIMD | gfx1030: VGPR / SGPR / scratch B / waves per SIMD | sm_80 (ptxas): registers / stack B / spill stores + loads B / warps per SM (of 64) |"
echo "|---|---|---|---|---|---|"
for precision in double float; do
  for loop in vector scalar; do
    "$source_tool" "$precision" "$loop" >"$tmp/k.cl"
    kernels=$(grep -A1 '__kernel' "$tmp/k.cl" | grep -o 'void [A-Za-z_0-9]*(' | sed 's/void //; s/($//' | paste -sd, -)
    amd gfx90a
    amd gfx1030
    nvidia
    for k in ${kernels//,/ }; do
      read -r v9 s9 c9 o9 <<<"$(field "$tmp/gfx90a.txt" "$k" 4)"
      read -r v10 s10 c10 o10 <<<"$(field "$tmp/gfx1030.txt" "$k" 4)"
      if [ -z "$ptxas" ]; then
        nv="ptxas not found"
      else
        read -r nr ns nst nld nw <<<"$(field "$tmp/sm_80.txt" "$k" 5)"
        nv="$nr / $ns / $nst + $nld / $nw"
      fi
      echo "| $k | $precision | $loop | $v9 / $s9 / $c9 / $o9 | $v10 / $s10 / $c10 / $o10 | $nv |"
    done
  done
done
