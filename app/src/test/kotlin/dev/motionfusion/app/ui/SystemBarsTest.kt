package dev.motionfusion.app.ui

import android.os.Build
import dev.motionfusion.app.platform.Sdks
import dev.motionfusion.app.offMainThread
import android.content.Context
import android.content.Intent
import android.graphics.Color
import android.view.View
import androidx.appcompat.app.AppCompatActivity
import androidx.core.graphics.Insets
import androidx.core.view.ViewCompat
import androidx.core.view.WindowInsetsCompat
import androidx.test.core.app.ActivityScenario
import androidx.test.core.app.ApplicationProvider
import androidx.test.ext.junit.runners.AndroidJUnit4
import com.google.android.material.color.MaterialColors
import dev.motionfusion.app.MainActivity
import dev.motionfusion.app.R
import dev.motionfusion.app.Screenshots
import dev.motionfusion.app.calibration.CalibrationActivity
import dev.motionfusion.app.sessions.SessionDetailActivity
import dev.motionfusion.app.sessions.SessionsActivity
import dev.motionfusion.app.settings.SettingsActivity
import org.junit.Assert.assertEquals
import org.junit.Assert.assertTrue
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.annotation.Config
import org.robolectric.annotation.GraphicsMode
import java.io.File

/**
 * Edge to edge on every screen (targetSdk 35 imposes it on Android 15): each activity, started
 * with androidx.test's ActivityScenario, draws behind transparent system bars and pads its
 * content by the insets the system sends (status bar, navigation bar, display cutout), without
 * adding them up when they are sent again; the Material 3 theme is light or dark as the system is.
 * Screenshots show the bars painted over each screen.
 */
@RunWith(AndroidJUnit4::class)
@GraphicsMode(GraphicsMode.Mode.NATIVE)
/*
 * From API 30, where insets are typed as the app reads them, to the newest. Under Robolectric, insets
 * dispatched to the decor view on 26 to 28 never reach the content below AppCompat's legacy decor, and
 * on 29 a display cutout does not; what those versions draw under the bars is left to a real phone
 * (docs/LIVE.md, "Android versions").
 */
@Config(minSdk = 30, maxSdk = Sdks.MAX)
class SystemBarsTest {
    private val app = ApplicationProvider.getApplicationContext<Context>()
    private val statusBar = 84
    private val navigationBar = 126
    private val cutout = 40

    private companion object {
        const val WIDTH = 1080
        const val HEIGHT = 1920
    }

    private fun <A : AppCompatActivity> check(scenario: ActivityScenario<A>, rootId: Int, screenshot: String, dark: Boolean = false) {
        scenario.use { it.onActivity { a ->
            assertEquals("status bar transparent", Color.TRANSPARENT, a.window.statusBarColor)
            val surface = MaterialColors.getColor(a, com.google.android.material.R.attr.colorSurface, Color.MAGENTA)
            assertEquals("Material 3 surface of the ${if (dark) "dark" else "light"} theme: ${Integer.toHexString(surface)}", dark, Color.luminance(surface) < 0.5f)
            // As the system does: the insets go to the window's decor view, twice (they must not add up).
            val insets = WindowInsetsCompat.Builder()
                .setInsets(WindowInsetsCompat.Type.systemBars(), Insets.of(0, statusBar, 0, navigationBar))
                .setInsets(WindowInsetsCompat.Type.displayCutout(), Insets.of(cutout, 0, 0, 0))
                .build()
            repeat(2) { ViewCompat.dispatchApplyWindowInsets(a.window.decorView, insets) }
            // One picture per version below the newest, to look at what each one draws.
            val name = if (Build.VERSION.SDK_INT < Sdks.MAX) "$screenshot-api${Build.VERSION.SDK_INT}" else screenshot
            Screenshots.capture(a, name, width = WIDTH, height = HEIGHT, systemBars = statusBar to navigationBar)
            // Nothing under the bars: the action bar's title (AppCompat places it) and the screen's content,
            // which is also kept clear of the cutout.
            val xy = IntArray(2)
            a.findViewById<View>(androidx.appcompat.R.id.action_bar)?.let { bar ->
                bar.getLocationInWindow(xy)
                assertTrue("action bar at ${xy[1]} under the status bar", xy[1] + bar.paddingTop >= statusBar)
            }
            val root = a.findViewById<View>(rootId)
            root.getLocationInWindow(xy)
            assertTrue("content top ${xy[1] + root.paddingTop} under the status bar", xy[1] + root.paddingTop >= statusBar)
            assertTrue("content left ${xy[0] + root.paddingLeft} under the cutout", xy[0] + root.paddingLeft >= cutout)
            val bottom = xy[1] + root.height - root.paddingBottom
            assertTrue("content bottom $bottom under the navigation bar", bottom <= HEIGHT - navigationBar)
            assertTrue("content does not leave a gap above the navigation bar: $bottom", bottom >= HEIGHT - navigationBar - 1)
        } }
    }

    @Test
    fun `the live screen`() = check(ActivityScenario.launch(MainActivity::class.java), R.id.live_root, "edge-to-edge-live")

    @Test
    @Config(qualifiers = "night")
    fun `the live screen in the dark theme`() = check(ActivityScenario.launch(MainActivity::class.java), R.id.live_root, "edge-to-edge-live-dark", dark = true)

    @Test
    fun `settings`() = check(ActivityScenario.launch(SettingsActivity::class.java), R.id.settings_root, "edge-to-edge-settings")

    @Test
    fun `the sessions list`() = check(ActivityScenario.launch(SessionsActivity::class.java), R.id.sessions_root, "edge-to-edge-sessions")

    @Test
    fun `the calibration`() = check(ActivityScenario.launch(CalibrationActivity::class.java), R.id.calibration_root, "edge-to-edge-calibration")

    @Test
    fun `a session's detail`() {
        offMainThread { File(File(app.filesDir, "sessions"), "empty session").mkdirs() }
        val intent = Intent(app, SessionDetailActivity::class.java).putExtra(SessionDetailActivity.EXTRA_SESSION, "empty session")
        check(ActivityScenario.launch<SessionDetailActivity>(intent), R.id.detail_root, "edge-to-edge-session-detail")
    }
}
