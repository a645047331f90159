package dev.motionfusion.app.calibration

import android.graphics.Bitmap
import android.graphics.Color
import android.os.Looper
import android.view.View
import android.widget.Button
import android.widget.TextView
import dev.motionfusion.app.MainActivity
import dev.motionfusion.app.R
import dev.motionfusion.app.Screenshots
import dev.motionfusion.app.TestGraph
import dev.motionfusion.app.record.RecordingState
import dev.motionfusion.core.calib.Calibration
import dev.motionfusion.core.calib.EllipsoidModel
import dev.motionfusion.core.calib.MagnetometerCalibration
import dev.motionfusion.core.calib.Matrix3
import dev.motionfusion.core.calib.SensorCorrection
import dev.motionfusion.core.event.SessionStream
import java.io.File
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.launch
import org.junit.Assert.assertEquals
import org.junit.Assert.assertFalse
import org.junit.Assert.assertTrue
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.Robolectric
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf
import org.robolectric.annotation.GraphicsMode

/**
 * The calibration screen in each state, portrait and landscape, light and dark, rendered to
 * target/screenshots/calibration-STATE-ORIENTATION-THEME.png, with the readings of the motion
 * simulator (known hard/soft iron, accelerometer and gyroscope errors) fed through a fake source.
 */
@RunWith(RobolectricTestRunner::class)
@GraphicsMode(GraphicsMode.Mode.NATIVE)
class CalibrationScreensTest {
    private fun idle() = shadowOf(Looper.getMainLooper()).idle()

    /** A phone held upright and sideways (400 × 860 dp at xhdpi), light and dark. */
    private val variants = listOf(
        "portrait-light" to "w400dp-h860dp-port-notnight-xhdpi", "portrait-dark" to "w400dp-h860dp-port-night-xhdpi",
        "landscape-light" to "w860dp-h400dp-land-notnight-xhdpi", "landscape-dark" to "w860dp-h400dp-land-night-xhdpi",
    )

    /** Renders [state] in the four variants; [act] brings a fresh screen into the state, [check] asserts on it and its picture. */
    private lateinit var graph: TestGraph

    private val storedMagnetometer = MagnetometerCalibration(
        SensorCorrection(SimulatedReadings.hardIron, Matrix3.IDENTITY), SessionStream.MAGNETOMETER_UNCALIBRATED, EllipsoidModel.SPHERE, 48.0, 0.4, 0.75, 4500, 20.0, 0.4,
    )

    private fun render(
        state: String, readings: List<CalibrationSample>, act: (CalibrationActivity) -> Unit,
        before: () -> Unit = {}, check: (CalibrationActivity, Bitmap) -> Unit,
    ) {
        for ((variant, qualifiers) in variants) {
            RuntimeEnvironment.setQualifiers(qualifiers)
            graph = TestGraph(calibrationSource = FakeSampleSource(readings))
            graph.settle()
            before()
            val c = Robolectric.buildActivity(CalibrationActivity::class.java).setup()
            val a = c.get()
            act(a)
            idle()
            val bitmap = Screenshots.captureScreen(a, "calibration-$state-$variant")
            val background = bitmap.getPixel(bitmap.width - 4, bitmap.height - 4)
            val luminance = (Color.red(background) * 0.3 + Color.green(background) * 0.59 + Color.blue(background) * 0.11) / 255
            if ("dark" in variant) assertTrue("$state $variant background $luminance", luminance < 0.3) else assertTrue("$state $variant background $luminance", luminance > 0.7)
            // The app bar: the screen's title and the way back, at the top.
            val toolbar = a.findViewById<androidx.appcompat.widget.Toolbar>(R.id.toolbar)
            assertEquals(a.getString(R.string.calibration_title), toolbar.title.toString())
            assertTrue("$state $variant: the up button", toolbar.navigationIcon != null)
            assertEquals(0, Screenshots.boundsInWindow(toolbar).top)
            assertEquals(if (state == "still-recording") View.VISIBLE else View.GONE, a.findViewById<View>(R.id.recording_banner).visibility)
            check(a, bitmap)
            c.pause().stop().destroy()
        }
    }

    private fun click(a: CalibrationActivity, id: Int) = a.findViewById<View>(id).performClick()
    private fun text(a: CalibrationActivity, id: Int) = a.findViewById<TextView>(id).text.toString()

    /** Cells drawn filled in the picture: each cell's centre compared with an empty cell's colour. */
    private fun filledCells(a: CalibrationActivity, b: Bitmap, emptyCell: Int): Int {
        val map = a.findViewById<CoverageMapView>(R.id.coverage_map)
        val at = IntArray(2).also { map.getLocationInWindow(it) }
        fun pixel(cell: Int) = map.cellCenter(cell).let { b.getPixel(at[0] + it.x.toInt(), at[1] + it.y.toInt()) }
        val empty = pixel(emptyCell)
        return (0 until 128).count { pixel(it) != empty }
    }

    @Test
    fun `starting`() = render("starting", emptyList(), {}) { a, b ->
        assertEquals(a.getString(R.string.calibration_mag_ready), text(a, R.id.instruction))
        assertEquals(a.getString(R.string.calibration_start), text(a, R.id.primary_action))
        assertFalse(a.findViewById<Button>(R.id.save).isEnabled)
        assertEquals(View.VISIBLE, a.findViewById<View>(R.id.coverage_map).visibility)
        assertEquals(0, filledCells(a, b, 0))
    }

    @Test
    fun `half covered`() = render("half-covered", readings.halfTurn, { click(it, R.id.primary_action) }) { a, b ->
        val s = a.viewModel.state.value
        assertEquals(CalibrationStage.COLLECTING, s.stage)
        assertTrue("coverage ${s.coverage}", s.coverage in 0.2..0.6)
        val covered = s.cellHits.count { it > 0 }
        val empty = s.cellHits.indexOfFirst { it == 0 }
        assertEquals(covered, filledCells(a, b, empty))
        assertEquals(a.getString(R.string.calibration_finish), text(a, R.id.primary_action))
        assertTrue(text(a, R.id.progress_text), text(a, R.id.progress_text).startsWith("${Math.round(100 * s.coverage)} % of directions covered (30 % needed)"))
    }

    @Test
    fun `fit accepted`() = render("mag-accepted", readings.fullTurn, { click(it, R.id.primary_action); click(it, R.id.primary_action) }) { a, b ->
        val r = text(a, R.id.result)
        assertTrue(r, r.startsWith("Magnetometer (uncalibrated readings; offset, scale and axis misalignment)\nHard iron  35.0 -20.0 60.0 µT"))
        assertTrue(r, Regex("Coverage \\d+ %").containsMatchIn(r))
        assertTrue(a.findViewById<Button>(R.id.save).isEnabled)
        assertEquals(a.getString(R.string.calibration_again), text(a, R.id.primary_action))
        assertTrue(filledCells(a, b, a.viewModel.state.value.cellHits.indexOfFirst { it == 0 }.coerceAtLeast(0)) > 64)
    }

    @Test
    fun `fit refused for poor coverage`() = render("mag-refused", readings.narrowTurn, { click(it, R.id.primary_action); click(it, R.id.primary_action) }) { a, _ ->
        assertEquals(a.getString(R.string.calibration_result_refused), text(a, R.id.instruction))
        assertTrue(text(a, R.id.result), Regex("^Magnetometer refused: the field directions cover 2\\d % of the sphere \\(at least 30 % needed\\)").containsMatchIn(text(a, R.id.result)))
        assertFalse(a.findViewById<Button>(R.id.save).isEnabled)
    }

    @Test
    fun `accelerometer pose 4 of 6`() = render("pose-4-of-6", readings.threePoses, { click(it, R.id.step_poses); click(it, R.id.primary_action) }) { a, _ ->
        assertEquals("Pose 4 of 6: Upside down", text(a, R.id.instruction))
        assertEquals(View.VISIBLE, a.findViewById<View>(R.id.pose_faces).visibility)
        assertEquals(View.GONE, a.findViewById<View>(R.id.coverage_map).visibility)
        assertEquals("3 of 6 faces held, next: Upside down", a.findViewById<View>(R.id.pose_faces).contentDescription)
        assertTrue(text(a, R.id.progress_text), text(a, R.id.progress_text).startsWith("3 poses · still "))
    }

    @Test
    fun `poses fitted`() = render("poses-accepted", readings.sixPoses, { click(it, R.id.step_poses); click(it, R.id.primary_action); click(it, R.id.primary_action) }) { a, _ ->
        val r = text(a, R.id.result)
        assertTrue(r, Regex("^Accelerometer \\(offset and scale per axis; 6 poses\\)\nOffset  0\\.1[12]\\d -0\\.(199|200|201) 0\\.1(49|50|51) m/s²").containsMatchIn(r))
        assertTrue(r, Regex("Gyroscope bias \\(uncalibrated readings\\)\nBias  0\\.0(099|100)\\d -0\\.0(199|200)\\d 0\\.01(49|50|51)\\d rad/s").containsMatchIn(r))
        assertTrue(a.findViewById<Button>(R.id.save).isEnabled)
        assertTrue(text(a, R.id.progress_text), Regex("^6 poses · \\d+ s$").matches(text(a, R.id.progress_text)))
    }

    @Test
    fun `calibration applied in the live filter`() = render("applied", emptyList(), {}, before = {
        val store = graph.graph.calibrationStore
        CoroutineScope(Dispatchers.Main.immediate).launch {
            store.accept(Calibration(magnetometer = storedMagnetometer, source = "test"))
        }
        graph.settle()
        store.setUseInLiveFilter(true)
    }) { a, _ ->
        assertTrue(a.findViewById<com.google.android.material.materialswitch.MaterialSwitch>(R.id.use_live).isChecked)
        assertEquals(a.getString(R.string.calibration_stored_applied, "magnetometer"), text(a, R.id.stored))
    }

    @Test
    fun `still recording under way`() = render("still-recording", emptyList(), { a ->
        click(a, R.id.step_still)
        val started = graph.clock.elapsedNs / 1_000_000
        graph.graph.recordings.set(RecordingState.Active(File(a.filesDir, "sessions/session_still"), started, { 1_843_200L }, still = true, streams = 2))
        graph.clock.elapsedNs += (38 * 60 + 25) * 1_000_000_000L
        shadowOf(Looper.getMainLooper()).idleFor(java.time.Duration.ofSeconds(1))
    }) { a, _ ->
        assertEquals(a.getString(R.string.calibration_still_recording), text(a, R.id.instruction))
        assertEquals("38:25 recorded · 1,843,200 samples\n" + a.getString(R.string.calibration_still_needs), text(a, R.id.progress_text))
        assertEquals(a.getString(R.string.calibration_still_stop), text(a, R.id.primary_action))
        assertEquals(64, a.findViewById<com.google.android.material.progressindicator.LinearProgressIndicator>(R.id.progress).progress)
        assertEquals(View.GONE, a.findViewById<View>(R.id.coverage_map).visibility)
        assertEquals(View.GONE, a.findViewById<View>(R.id.save).visibility)
        assertEquals("Still recording 38:25 · 2 streams", text(a, R.id.recording_banner_text))
    }

    @Test
    fun `still recording explained`() = render("still-ready", emptyList(), { click(it, R.id.step_still) }) { a, _ ->
        assertEquals(a.getString(R.string.calibration_still_ready), text(a, R.id.instruction))
        assertEquals(a.getString(R.string.calibration_still_needs), text(a, R.id.progress_text))
        assertEquals(a.getString(R.string.calibration_still_start), text(a, R.id.primary_action))
    }

    @Test
    fun `the main screen's menu opens the calibration`() {
        val main = Robolectric.buildActivity(MainActivity::class.java).setup().get()
        assertTrue(shadowOf(main).clickMenuItem(R.id.open_calibration))
        assertEquals(CalibrationActivity::class.java.name, shadowOf(main).nextStartedActivity.component!!.className)
    }

    /** Simulated readings, made once. */
    private object readings {
        val halfTurn by lazy { SimulatedReadings.turning(2.5, 25.0) }
        val fullTurn by lazy { SimulatedReadings.turning(2.5, 90.0) }
        val narrowTurn by lazy { SimulatedReadings.turning(1.5, 60.0) }
        val threePoses by lazy { SimulatedReadings.poses(SimulatedReadings.faces.take(3)) }
        val sixPoses by lazy { SimulatedReadings.poses(SimulatedReadings.faces) }
    }
}
