package dev.motionfusion.app

import dev.motionfusion.app.platform.MainThreadPolicy

/**
 * The application of every Robolectric test (`robolectric.properties`): the app, with StrictMode
 * throwing at the first disk read, disk write or network call on the main thread, so a test
 * whose main thread does one fails there (MainThreadPolicyTest shows that it does).
 */
internal class StrictTestApp : MotionFusionApp() {
    override fun installMainThreadPolicy() = MainThreadPolicy.install(fail = true)
}
