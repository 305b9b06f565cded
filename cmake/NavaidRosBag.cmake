# ROS 1 bag storage from Debian's ROS packages (thirdparty-notes/rosbag.md). Their catkin CMake
# configs pull in ROS 2's ament through pluginlib, so the target is made here from the libraries
# and headers themselves. An imported target's headers are system headers: their warnings are not ours.
if(NOT TARGET NavaidRos::rosbag)
  find_path(NAVAID_ROSBAG_INCLUDE_DIR rosbag/bag.h REQUIRED)
  find_path(NAVAID_PLUGINLIB_INCLUDE_DIR pluginlib/class_loader.hpp PATH_SUFFIXES pluginlib REQUIRED)
  find_path(NAVAID_CLASS_LOADER_INCLUDE_DIR class_loader/class_loader.hpp PATH_SUFFIXES class_loader REQUIRED)
  find_path(NAVAID_RCUTILS_INCLUDE_DIR rcutils/types.h PATH_SUFFIXES rcutils REQUIRED)
  find_path(NAVAID_RCPPUTILS_INCLUDE_DIR rcpputils/filesystem_helper.hpp PATH_SUFFIXES rcpputils REQUIRED)
  find_path(NAVAID_AMENT_INDEX_INCLUDE_DIR ament_index_cpp/get_resource.hpp PATH_SUFFIXES ament_index_cpp REQUIRED)
  find_path(NAVAID_SENSOR_MSGS_INCLUDE_DIR sensor_msgs/Imu.h REQUIRED)
  find_path(NAVAID_TF2_MSGS_INCLUDE_DIR tf2_msgs/TFMessage.h REQUIRED)
  foreach(lib rosbag_storage roscpp_serialization rostime cpp_common console_bridge roslz4 bz2)
    find_library(NAVAID_ROS_${lib}_LIBRARY ${lib} REQUIRED)
    list(APPEND NAVAID_ROS_LIBRARIES ${NAVAID_ROS_${lib}_LIBRARY})
  endforeach()
  add_library(NavaidRos::rosbag INTERFACE IMPORTED)
  set_target_properties(NavaidRos::rosbag PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${NAVAID_ROSBAG_INCLUDE_DIR};${NAVAID_PLUGINLIB_INCLUDE_DIR};${NAVAID_CLASS_LOADER_INCLUDE_DIR};${NAVAID_RCUTILS_INCLUDE_DIR};${NAVAID_RCPPUTILS_INCLUDE_DIR};${NAVAID_AMENT_INDEX_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${NAVAID_ROS_LIBRARIES}")
endif()
