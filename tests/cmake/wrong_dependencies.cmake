# A tree as it stood before issue 35, for dependency_check_refuses_a_wrong_link: host/device
# links the tool module and adds its include folder. The check must refuse it.
list(APPEND CATHBOX_TARGETS cathbox_device)
set(cathbox_device_DIR "host/device")
set(cathbox_device_LINKS "cathbox::protocol;cathbox::base;cathbox_tool")
set(cathbox_device_INCLUDES "${SOURCE_DIR}/host/device/include;${SOURCE_DIR}/sim/tool/include")
