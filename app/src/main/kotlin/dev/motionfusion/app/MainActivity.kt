package dev.motionfusion.app

import android.app.Activity
import android.content.Intent
import android.os.Build
import android.os.Bundle
import android.view.Choreographer
import android.view.Surface
import dev.motionfusion.app.live.FusionEngine
import dev.motionfusion.app.live.FusionState
import dev.motionfusion.app.live.LiveEngines
import dev.motionfusion.app.live.LiveScreen
import dev.motionfusion.app.settings.SettingsActivity

/**
 * The live screen. The fusion runs in the process-wide [FusionEngine] (off the main thread, and
 * surviving configuration changes); this activity only keeps it running while visible
 * (onStart..onStop) and draws its latest state once per display frame.
 */
class MainActivity : Activity() {
    private lateinit var engine: FusionEngine
    private lateinit var screen: LiveScreen
    private var shown: FusionState? = null
    private var shownRotation = -1
    private var visible = false

    private val frame = object : Choreographer.FrameCallback {
        override fun doFrame(frameTimeNanos: Long) {
            if (!visible) return
            render()
            Choreographer.getInstance().postFrameCallback(this)
        }
    }

    override fun onCreate(savedInstanceState: Bundle?) {
        super.onCreate(savedInstanceState)
        setContentView(R.layout.activity_main)
        engine = LiveEngines.get(this)
        screen = LiveScreen(this, engine.sensorInfo)
        findViewById<android.view.View>(R.id.open_settings).setOnClickListener {
            startActivity(Intent(this, SettingsActivity::class.java))
        }
        render()
    }

    override fun onStart() {
        super.onStart()
        engine.start()
        visible = true
        Choreographer.getInstance().postFrameCallback(frame)
    }

    override fun onStop() {
        visible = false
        Choreographer.getInstance().removeFrameCallback(frame)
        engine.stop()
        super.onStop()
    }

    /** Draws the engine's latest state when it or the display rotation changed since the last frame. */
    private fun render() {
        val s = engine.state.value
        val rotation = displayRotation()
        if (s === shown && rotation == shownRotation) return
        shown = s
        shownRotation = rotation
        screen.show(s, rotation)
    }

    /** Surface.ROTATION_0..270 of the display this activity is on (read each frame: 180° turns raise no event). */
    private fun displayRotation(): Int {
        val d = if (Build.VERSION.SDK_INT >= Build.VERSION_CODES.R) display else {
            @Suppress("DEPRECATION")
            windowManager.defaultDisplay
        }
        return d?.rotation ?: Surface.ROTATION_0
    }
}
