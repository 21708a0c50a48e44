#!/usr/bin/env sh
# generated from catkin/python/catkin/environment_cache.py

# based on a snapshot of the environment before and after calling the setup script
# it emulates the modifications of the setup script without recurring computations

# new environment variables
export CMAKE_PREFIX_PATH='/work/main/build_particle/devel'
export LD_LIBRARY_PATH='/work/main/build_particle/devel/lib'
export PKG_CONFIG_PATH='/work/main/build_particle/devel/lib/pkgconfig'
export PYTHONPATH=''
export ROS_DISTRO='Debian'
export ROS_ETC_DIR='//etc/ros'
export ROS_MASTER_URI='http://localhost:11311'
export ROS_PACKAGE_PATH='/work/main'
export ROS_PYTHON_VERSION='3'
export ROS_VERSION='1'

# modified environment variables
export PWD='/work/main/build_particle'