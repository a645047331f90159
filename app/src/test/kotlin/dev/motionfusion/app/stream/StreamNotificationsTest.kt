package dev.motionfusion.app.stream

import android.Manifest
import android.content.pm.PackageManager
import android.os.Looper
import android.widget.CompoundButton
import android.widget.TextView
import androidx.appcompat.app.AlertDialog
import dev.motionfusion.app.R
import dev.motionfusion.app.Screenshots
import dev.motionfusion.app.TestGraph
import dev.motionfusion.app.platform.Sdks
import org.junit.Assert.assertEquals
import org.junit.Assert.assertNotEquals
import org.junit.Assert.assertNull
import org.junit.Assert.assertTrue
import org.junit.Before
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.Robolectric
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf
import org.robolectric.annotation.Config
import org.robolectric.annotation.GraphicsMode

/**
 * The stream's foreground service shows a notification with its Stop: on Android 13+ the first
 * stream explains it and asks for the permission, as the first recording does (one question for
 * the app); before 13 nothing is asked.
 */
@RunWith(RobolectricTestRunner::class)
class StreamNotificationsTest {
    private val app = RuntimeEnvironment.getApplication()
    private lateinit var graph: TestGraph

    @Before
    fun setUp() {
        graph = TestGraph()
    }

    private fun screen() = Robolectric.buildActivity(StreamActivity::class.java).setup()

    @Test
    @Config(minSdk = 33, maxSdk = Sdks.MAX, qualifiers = "w400dp-h860dp-port-xhdpi")
    @GraphicsMode(GraphicsMode.Mode.NATIVE)
    fun `API 33+, the first stream explains its notification and asks, then streams whatever the answer, once`() {
        val c = screen()
        val a = c.get()
        a.findViewById<CompoundButton>(R.id.stream_switch).performClick()
        val dialog = a.notifications.dialog ?: error("no explanation")
        assertTrue(dialog.isShowing)
        assertEquals(a.getString(R.string.stream_notifications_text), dialog.findViewById<TextView>(android.R.id.message)!!.text.toString())
        assertEquals("not started before the answer", StreamState.Off, graph.graph.stream.state.value)
        shadowOf(Looper.getMainLooper()).idle()
        if (android.os.Build.VERSION.SDK_INT == Sdks.MAX) Screenshots.captureDialog(a, dialog, "stream-notifications-explained")
        dialog.getButton(AlertDialog.BUTTON_POSITIVE).performClick()
        shadowOf(Looper.getMainLooper()).idle()
        val request = shadowOf(a).lastRequestedPermission!!
        assertEquals(Manifest.permission.POST_NOTIFICATIONS, request.requestedPermissions.single())
        a.onRequestPermissionsResult(request.requestCode, request.requestedPermissions, intArrayOf(PackageManager.PERMISSION_DENIED))
        shadowOf(Looper.getMainLooper()).idle()
        assertNotEquals("started after the answer", StreamState.Off, graph.graph.stream.state.value)
        assertTrue(graph.graph.notificationsAnswered)
        graph.graph.stream.stop()
        graph.settle()
        c.pause().stop().destroy()
        // Asked once for the app: the recording's Record does not ask again, nor does the next stream.
        val again = screen().get()
        again.findViewById<CompoundButton>(R.id.stream_switch).performClick()
        assertNull(again.notifications.dialog)
        assertNotEquals(StreamState.Off, graph.graph.stream.state.value)
        graph.graph.stream.stop()
        graph.settle()
    }

    @Test
    @Config(minSdk = Sdks.MIN, maxSdk = 32)
    fun `before API 33 the stream starts at once`() {
        val a = screen().get()
        a.findViewById<CompoundButton>(R.id.stream_switch).performClick()
        assertNull(a.notifications.dialog)
        assertNull(shadowOf(a).lastRequestedPermission)
        assertNotEquals(StreamState.Off, graph.graph.stream.state.value)
        graph.graph.stream.stop()
        graph.settle()
    }
}
