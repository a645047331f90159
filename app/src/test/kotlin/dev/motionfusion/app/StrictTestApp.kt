package dev.motionfusion.app

import dev.motionfusion.app.platform.MainThreadPolicy

/**
 * The application of every Robolectric test (robolectric.properties): the app with StrictMode
 * throwing on disk and network work on the main thread, so a test that does it fails.
 */
internal class StrictTestApp : MotionFusionApp() {
    override fun onCreate() {
        super.onCreate()
        MainThreadPolicy.install(fail = true)
    }
}
