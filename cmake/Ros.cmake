# Optional ROS 1 support from the Debian packages (no catkin): rosbag input (library dloam_ros)
# and the dloam_node program. Turned off, with a message, when the packages are missing.
option(DLOAM_WITH_ROS "Build rosbag input and the ROS 1 node when the Debian ROS packages are found" ON)
if(DLOAM_WITH_ROS)
  # ROS's CMake configs run Python: use Debian's, which sees the ROS Python modules (a pyenv
  # python3 on PATH does not). Their pkg-config files are incomplete, so use the CMake configs.
  set(Python3_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Python for the ROS CMake configs")
  find_package(rosbag_storage CONFIG QUIET)
  find_package(sensor_msgs CONFIG QUIET)
  if(NOT rosbag_storage_FOUND OR NOT sensor_msgs_FOUND)
    message(STATUS "dloam: ROS packages not found (librosbag-storage-dev libsensor-msgs-dev): "
                   "building without rosbag input and dloam_node")
    set(DLOAM_WITH_ROS OFF)
  endif()
endif()
