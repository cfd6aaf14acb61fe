# Source on a GPU machine prepared by tools/gpu_bundle.sh: the bundled libraries first, the
# NVIDIA OpenCL driver registered through an ICD file of our own (OCL_ICD_VENDORS).
#   source tools/gpu_env.sh
_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
_nv=$(ldconfig -p 2>/dev/null | awk '/libnvidia-opencl\.so\.1/{print $NF; exit}')
[ -n "$_nv" ] || _nv=$(find / -xdev -name 'libnvidia-opencl.so.1' 2>/dev/null | head -1)
[ -n "$_nv" ] || _nv=$(find /usr/local/nvidia /usr/lib* -name 'libnvidia-opencl.so*' 2>/dev/null | head -1)
export OCL_ICD_VENDORS=/tmp/sphsolid-icd
mkdir -p "$OCL_ICD_VENDORS"
echo "${_nv:-libnvidia-opencl.so.1}" >"$OCL_ICD_VENDORS/nvidia.icd"
export LD_LIBRARY_PATH="$_root/.ocl/lib${_nv:+:$(dirname "$_nv")}${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export POCL_CACHE_DIR=/tmp/pocl-cache OMP_WAIT_POLICY=passive PYTHONUNBUFFERED=1
echo "gpu_env: NVIDIA OpenCL driver: ${_nv:-not found}; ICD file $OCL_ICD_VENDORS/nvidia.icd"
unset _root _nv
