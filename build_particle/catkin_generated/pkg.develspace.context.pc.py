# generated from catkin/cmake/template/pkg.context.pc.in
CATKIN_PACKAGE_PREFIX = ""
PROJECT_PKG_CONFIG_INCLUDE_DIRS = "/work/main/include".split(';') if "/work/main/include" != "" else []
PROJECT_CATKIN_DEPENDS = "".replace(';', ' ')
PKG_CONFIG_LIBRARIES_WITH_PREFIX = "-lcloth_hair_sim_core".split(';') if "-lcloth_hair_sim_core" != "" else []
PROJECT_NAME = "cloth_hair_sim"
PROJECT_SPACE_DIR = "/work/main/build_particle/devel"
PROJECT_VERSION = "0.1.0"
PROJECT_LIB_DIR = "lib"
