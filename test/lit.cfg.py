# -*- Python -*-
import os

import lit.formats
from lit.llvm import llvm_config

config.name = "osl-mlir"
config.test_format = lit.formats.ShTest(not llvm_config.use_lit_shell)
config.suffixes = [".mlir", ".osl"]
config.test_source_root = os.path.dirname(__file__)
config.test_exec_root = os.path.join(config.osl_obj_root, "test")
config.excludes = ["Inputs", "CMakeLists.txt", "lit.cfg.py", "lit.site.cfg.py", "farm"]

config.substitutions.append(("%shaders", os.path.join(config.osl_src_root, "shaders")))
# python/oslquery.py as the build lays it out, beside bin/osl-run.
# lib/osl.imageio.so, found by OpenImageIO on OIIO_LIBRARY_PATH.
config.substitutions.append(("%osl_lib", os.path.join(config.osl_obj_root, "lib")))
config.substitutions.append(("%pymodules", os.path.join(config.osl_obj_root, "python")))
config.substitutions.append(("%conformance", os.path.join(config.osl_src_root, "conformance")))

llvm_config.with_system_environment(["HOME", "INCLUDE", "LIB", "TMP", "TEMP"])
llvm_config.with_environment("PATH", config.llvm_tools_dir, append_path=True)
llvm_config.use_default_substitutions()
tool_dirs = [config.osl_tools_dir, config.llvm_tools_dir]
llvm_config.add_tool_substitutions(["osl-opt", "osl-run", "osl-imgdiff"], tool_dirs)
