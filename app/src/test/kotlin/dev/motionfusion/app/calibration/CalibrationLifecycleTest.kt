package dev.motionfusion.app.calibration

import android.os.Looper
import android.view.View
import android.view.WindowManager
import dev.motionfusion.app.R
import dev.motionfusion.app.TestGraph
import org.junit.Assert.assertEquals
import org.junit.Assert.assertSame
import org.junit.Assert.assertTrue
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.Robolectric
import org.robolectric.RobolectricTestRunner
import org.robolectric.Shadows.shadowOf
import org.robolectric.android.controller.ActivityController

/**
 * A calibration a person can finish: the screen stays on while the phone is turned through or
 * posed, and a step under way survives a rotation (the activity recreated) and the screen going
 * off (stop, then start), keeping what it collected.
 */
@RunWith(RobolectricTestRunner::class)
class CalibrationLifecycleTest {
    private fun idle() = shadowOf(Looper.getMainLooper()).idle()

    private fun keepsScreenOn(a: CalibrationActivity) = a.window.attributes.flags and WindowManager.LayoutParams.FLAG_KEEP_SCREEN_ON != 0

    private fun open(source: FakeSampleSource): ActivityController<CalibrationActivity> {
        TestGraph(calibrationSource = source).settle()
        return Robolectric.buildActivity(CalibrationActivity::class.java).setup()
    }

    @Test
    fun `the turn-through keeps the screen on, survives the screen going off and a rotation, and keeps its readings`() {
        val source = FakeSampleSource(SimulatedReadings.turning(2.5, 25.0))
        val c = open(source)
        assertTrue("not before the start", !keepsScreenOn(c.get()))
        c.get().findViewById<View>(R.id.primary_action).performClick()
        idle()
        val vm = c.get().viewModel
        val collected = vm.state.value.magSamples
        assertEquals(CalibrationStage.COLLECTING, vm.state.value.stage)
        assertTrue(collected > 1000)
        assertTrue("kept on while turning", keepsScreenOn(c.get()))

        // The screen turns off: the sensors are let go, the step and its readings stay.
        c.pause().stop()
        idle()
        assertEquals(CalibrationStage.COLLECTING, vm.state.value.stage)
        assertEquals(CalibrationStep.MAGNETOMETER, vm.state.value.step)
        assertEquals(collected, vm.state.value.magSamples)
        // Back on: collecting goes on from there (the fake delivers its readings again).
        c.start().resume()
        idle()
        assertEquals(2, source.collections)
        assertEquals(CalibrationStage.COLLECTING, vm.state.value.stage)
        assertTrue("${vm.state.value.magSamples} after $collected", vm.state.value.magSamples > collected)
        val coverage = vm.state.value.coverage

        // A rotation: the same step, the same readings, still kept on; the sensors are not re-registered.
        c.recreate()
        idle()
        val a = c.get()
        assertSame(vm, a.viewModel)
        assertEquals(CalibrationStage.COLLECTING, vm.state.value.stage)
        assertEquals(coverage, vm.state.value.coverage, 0.0)
        assertEquals(2, source.collections)
        assertTrue(keepsScreenOn(a))

        a.findViewById<View>(R.id.primary_action).performClick()
        idle()
        assertEquals(CalibrationStage.RESULT, vm.state.value.stage)
        assertTrue("off once the step is done", !keepsScreenOn(a))
        c.pause().stop().destroy()
    }

    @Test
    fun `the poses step survives a rotation without going back to the turn-through`() {
        val c = open(FakeSampleSource(SimulatedReadings.poses(SimulatedReadings.faces.take(3))))
        c.get().findViewById<View>(R.id.step_poses).performClick()
        c.get().findViewById<View>(R.id.primary_action).performClick()
        idle()
        val vm = c.get().viewModel
        val held = vm.state.value.facesHeld
        assertEquals(3, held.size)
        c.recreate()
        idle()
        assertEquals(CalibrationStep.POSES, vm.state.value.step)
        assertEquals(CalibrationStage.COLLECTING, vm.state.value.stage)
        assertEquals(held, vm.state.value.facesHeld)
        assertTrue(keepsScreenOn(c.get()))
        c.pause().stop()
        c.start().resume()
        idle()
        assertEquals(CalibrationStep.POSES, vm.state.value.step)
        assertEquals(CalibrationStage.COLLECTING, vm.state.value.stage)
        c.pause().stop().destroy()
    }
}
