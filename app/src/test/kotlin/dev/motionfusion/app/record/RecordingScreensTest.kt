package dev.motionfusion.app.record

import android.content.Intent
import android.graphics.Bitmap
import android.graphics.Canvas
import android.graphics.Color
import android.hardware.Sensor
import android.hardware.SensorManager
import android.os.Looper
import android.view.View
import android.widget.Button
import android.widget.TextView
import androidx.appcompat.app.AlertDialog
import dev.motionfusion.app.MainActivity
import dev.motionfusion.app.R
import dev.motionfusion.app.Screenshots
import dev.motionfusion.app.TestGraph
import dev.motionfusion.app.sensor.SensorStreams
import dev.motionfusion.core.session.SessionStream
import org.junit.Assert.assertEquals
import org.junit.Assert.assertTrue
import org.junit.Before
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.Robolectric
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf
import org.robolectric.annotation.Config
import org.robolectric.shadows.SensorBuilder
import org.robolectric.shadows.SensorEventBuilder
import org.robolectric.shadows.ShadowDialog
import java.io.File
import java.time.Duration
import kotlin.math.sin

/** The recording's own states on screen, rendered to PNG (target/screenshots): a real recording with markers, and the notification explanation. */
@RunWith(RobolectricTestRunner::class)
@Config(sdk = [34])
class RecordingScreensTest {
    private val app = RuntimeEnvironment.getApplication()
    private lateinit var all: Map<SessionStream, Sensor>
    private lateinit var graph: TestGraph

    @Before
    fun setUp() {
        val sm = shadowOf(app.getSystemService(SensorManager::class.java))
        all = SensorStreams.all.associateWith { s ->
            SensorBuilder.newBuilder().setType(s.androidType).setName("BMI260 ${s.name.lowercase()}").setMaximumRange(34.9f).build().also(sm::addSensor)
        }
        graph = TestGraph()
    }

    private fun idle() = shadowOf(Looper.getMainLooper()).idle()

    /** A phone swaying in the hand for [seconds] from [t0]: gravity and the magnetic field turning slowly. */
    private fun sway(t0: Long, seconds: Double) {
        val sm = shadowOf(app.getSystemService(SensorManager::class.java))
        val n = (seconds * 100).toInt()
        for (i in 0 until n) {
            val t = t0 + i * 10_000_000L
            val s = i / 100.0
            val roll = 0.4 * sin(0.8 * s)
            fun send(stream: SessionStream, v: FloatArray) = sm.sendSensorEventToListeners(
                SensorEventBuilder.newBuilder().setSensor(all.getValue(stream)).setValues(v).setTimestamp(t)
                    .setAccuracy(SensorManager.SENSOR_STATUS_ACCURACY_HIGH).build(),
            )
            send(SessionStream.ACCELEROMETER, floatArrayOf((9.81 * sin(roll)).toFloat(), 3.0f, (9.81 * kotlin.math.cos(roll)).toFloat()))
            send(SessionStream.MAGNETOMETER, floatArrayOf(5f, 20f, -40f))
            send(SessionStream.GYROSCOPE, floatArrayOf((0.32 * kotlin.math.cos(0.8 * s)).toFloat(), 0.01f, 0.02f))
            if (i % 50 == 0) graph.pump()
        }
        graph.pump()
    }

    private fun configure(land: Boolean, dark: Boolean) =
        RuntimeEnvironment.setQualifiers("${if (land) "w860dp-h400dp-land" else "w400dp-h860dp-port"}-${if (dark) "night" else "notnight"}-xhdpi")

    @Test
    fun `a recording with markers, portrait`() {
        for (land in listOf(false)) for (dark in listOf(false, true)) {
            configure(land, dark)
            graph = TestGraph()
            graph.graph.setNotificationsAnswered()
            val controller = Robolectric.buildActivity(MainActivity::class.java).setup()
            val a = controller.get()
            a.findViewById<Button>(R.id.record_toggle).performClick()
            idle()
            val service = Robolectric.buildService(RecordingService::class.java, shadowOf(app).nextStartedService).create().startCommand(0, 1)
            graph.settle()
            val t0 = graph.clock.elapsedNs
            sway(t0, 4.0)
            graph.clock.elapsedNs = t0 + 4_000_000_000L
            a.findViewById<Button>(R.id.record_mark).performClick()
            sway(t0 + 4_000_000_000L, 3.0)
            graph.clock.elapsedNs = t0 + 7_000_000_000L
            a.findViewById<Button>(R.id.record_mark).performLongClick()
            idle()
            val note = ShadowDialog.getLatestDialog() as AlertDialog
            note.findViewById<android.widget.EditText>(R.id.record_mark_input)!!.setText("stairs up")
            note.getButton(AlertDialog.BUTTON_POSITIVE).performClick()
            sway(t0 + 7_000_000_000L, 4.0)
            graph.clock.elapsedNs = t0 + 83_000_000_000L
            shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(1))
            val status = a.findViewById<TextView>(R.id.record_status).text.toString()
            assertTrue(status, status.contains("01:23") && status.contains("2 markers"))
            assertEquals(View.VISIBLE, a.findViewById<View>(R.id.record_mark).visibility)
            val name = "recording-markers-${if (land) "landscape" else "phone"}-${if (dark) "dark" else "light"}"
            Screenshots.captureScreen(a, name)
            val plot = a.findViewById<View>(R.id.plot)
            plot.requestRectangleOnScreen(android.graphics.Rect(0, 0, plot.width, plot.height), true)
            Screenshots.captureScreen(a, "$name-plot")
            service.get().onStartCommand(Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_STOP), 0, 2)
            graph.pump()
            graph.settle()
            controller.pause().stop().destroy()
        }
    }

    @Test
    fun `the notification explanation before the first recording`() {
        for (dark in listOf(false, true)) {
            configure(land = false, dark = dark)
            graph = TestGraph()
            val controller = Robolectric.buildActivity(MainActivity::class.java).setup()
            val a = controller.get()
            a.findViewById<Button>(R.id.record_toggle).performClick()
            idle()
            val dialog = ShadowDialog.getLatestDialog() as AlertDialog
            assertTrue(dialog.isShowing)
            val name = "record-notification-explanation-phone-${if (dark) "dark" else "light"}"
            val screen = Screenshots.captureScreen(a, name)
            // The dialog's own window over the screen, as the phone shows it.
            val d = dialog.window!!.decorView
            val w = screen.width - 96
            d.measure(View.MeasureSpec.makeMeasureSpec(w, View.MeasureSpec.EXACTLY), View.MeasureSpec.makeMeasureSpec(screen.height, View.MeasureSpec.AT_MOST))
            d.layout(0, 0, d.measuredWidth, d.measuredHeight)
            val out = screen.copy(Bitmap.Config.ARGB_8888, true)
            val canvas = Canvas(out)
            canvas.drawColor(Color.argb(0x99, 0, 0, 0))
            canvas.translate(48f, (screen.height - d.measuredHeight) / 2f)
            d.draw(canvas)
            val dir = File(System.getProperty("screenshots.dir") ?: "target/screenshots")
            File(dir, "$name.png").outputStream().use { out.compress(Bitmap.CompressFormat.PNG, 100, it) }
            controller.pause().stop().destroy()
        }
    }
}
