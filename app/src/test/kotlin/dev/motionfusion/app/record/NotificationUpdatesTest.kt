package dev.motionfusion.app.record

import android.app.Notification
import android.app.NotificationManager
import android.content.Intent
import android.hardware.Sensor
import android.hardware.SensorManager
import android.os.Looper
import dev.motionfusion.app.TestGraph
import org.junit.Assert.assertEquals
import org.junit.Assert.assertTrue
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.Robolectric
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf
import org.robolectric.shadows.SensorBuilder
import java.time.Duration

/**
 * The recording's notification is posted a few times a minute, not every second: its text (time
 * and sample count) every [RecordingService.NOTIFICATION_UPDATE_TICKS] s, the shade's chronometer
 * counting meanwhile; the Stop action keeps working across the updates.
 */
@RunWith(RobolectricTestRunner::class)
class NotificationUpdatesTest {
    private val app = RuntimeEnvironment.getApplication()

    @Test
    fun `a minute of recording posts the notification twelve times, not sixty`() {
        val sm = shadowOf(app.getSystemService(SensorManager::class.java))
        for (type in listOf(Sensor.TYPE_ACCELEROMETER, Sensor.TYPE_GYROSCOPE)) sm.addSensor(SensorBuilder.newBuilder().setType(type).setName("Test $type").build())
        val graph = TestGraph()
        val c = Robolectric.buildService(RecordingService::class.java, Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_START)).create().startCommand(0, 1)
        graph.settle()
        assertTrue(graph.graph.recordings.isRecording)
        val before = c.get().notificationUpdates
        for (s in 1..60) {
            graph.clock.elapsedNs += 1_000_000_000L
            shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(1))
        }
        assertEquals(12, c.get().notificationUpdates - before)
        val n = shadowOf(app.getSystemService(NotificationManager::class.java)).getNotification(RecordingService.NOTIFICATION_ID)
        assertTrue(n.flags and Notification.FLAG_ONGOING_EVENT != 0)
        assertEquals(RecordingService.ACTION_STOP, shadowOf(n.actions.single().actionIntent).savedIntent.action)
        c.get().onStartCommand(Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_STOP), 0, 2)
        graph.pump()
        graph.settle()
    }
}
