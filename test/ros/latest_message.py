"""The latest message on a topic, kept for a test thread to read (the subscriber's callback runs on
rospy's own thread)."""
import threading

import rospy


class LatestMessage(object):
    def __init__(self, topic, message_type):
        self._lock = threading.Lock()
        self._message = None
        rospy.Subscriber(topic, message_type, self._store)

    def _store(self, msg):
        with self._lock:
            self._message = msg

    def get(self):
        """The latest message, or None before the first one."""
        with self._lock:
            return self._message
