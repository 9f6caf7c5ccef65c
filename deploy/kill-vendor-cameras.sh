#!/bin/sh
# Stop the vendor camera producers so /dev/video* are free for Lupin (seed: ExecStartPre
# scripts/kill-vendor-cameras.sh). Exact process names only; nothing else is touched.
# Exit 0 whether or not they were running: "not running" is the state we want.
for name in usb_cam_node_exe component_container astra_camera_node web_video_server; do
    pkill -INT -x "$name" 2>/dev/null
done
sleep 1
for name in usb_cam_node_exe component_container astra_camera_node web_video_server; do
    pkill -KILL -x "$name" 2>/dev/null
done
exit 0
